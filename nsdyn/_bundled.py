"""Where the data files shipped with nsdyn are found: one lookup for frames and records alike.

A bundled set is a folder of files with one suffix. Installed, it is the package
``nsdyn.data.<set>`` (package data); in a source checkout, where that package holds no such
file, it is the folder ``<repo>/<set>`` at the repository root. A file's bundled name is its
name without the suffix.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from importlib.resources.abc import Traversable
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]  # the checkout holding nsdyn/ (source tree)


@dataclass(frozen=True)
class BundledSet:
    """The bundled files of one kind: package ``package`` or ``<repo>/<folder>``, ``*suffix``."""

    package: str
    folder: str
    suffix: str

    def root(self) -> Traversable | Path:
        """The installed package if it holds a ``*suffix`` file, else ``<repo>/<folder>``."""
        try:
            root = resources.files(self.package)
            if any(p.name.endswith(self.suffix) for p in root.iterdir()):
                return root
        except (ModuleNotFoundError, FileNotFoundError, NotADirectoryError):
            pass
        return REPO_ROOT / self.folder

    def names(self) -> list[str]:
        """Sorted bundled names (file names without the suffix); [] when the folder is absent."""
        try:
            files = [p.name for p in self.root().iterdir()]
        except FileNotFoundError:
            return []
        return sorted(f[: -len(self.suffix)] for f in files if f.endswith(self.suffix))

    def find(self, name: str) -> Traversable | Path | None:
        """The bundled file ``<name><suffix>``, or None if there is none."""
        item = self.root() / f"{name}{self.suffix}"
        return item if item.is_file() else None


FRAMES = BundledSet("nsdyn.data.frames", "frames", ".toml")  # frame definitions
RECORDS = BundledSet("nsdyn.data.records", "records", ".csv")  # synthetic ground motions
