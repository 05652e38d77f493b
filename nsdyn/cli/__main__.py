"""``python -m nsdyn.cli``: the same as the ``nsdyn`` script."""

import sys

from nsdyn.cli.app import script

sys.exit(script())
