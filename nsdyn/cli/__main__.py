"""``python -m nsdyn.cli``: the same as the ``nsdyn`` script."""

import sys

from nsdyn.cli.app import main

sys.exit(main())
