"""MkDocs hook: lay the source folders out under their installed names for the API reference.

The repository keeps ``geometry/``, ``importers/`` and ``solver/`` at its top and installs them as
``ibfem.geometry``, ``ibfem.importers`` and ``ibfem.solver``. The API reference reads the source
statically, so before the build this hook makes ``build/api-source/ibfem/`` with links to those
folders (copies where the file system has no symbolic links); mkdocs.yml points the Python
handler there.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from mkdocs.plugins import event_priority

SUBPACKAGES = ("geometry", "importers", "solver")


def _link(target: Path, link: Path) -> None:
    if link.is_symlink() or link.is_file():
        link.unlink()
    elif link.is_dir():
        shutil.rmtree(link)
    try:
        os.symlink(target, link, target_is_directory=target.is_dir())
    except OSError:
        (shutil.copytree if target.is_dir() else shutil.copy2)(target, link)


@event_priority(100)  # before mkdocstrings reads its search paths
def on_config(config, **kwargs):
    root = Path(config["config_file_path"]).resolve().parent
    package = root / "build" / "api-source" / "ibfem"
    package.mkdir(parents=True, exist_ok=True)
    _link(root / "ibfem" / "__init__.py", package / "__init__.py")
    for name in SUBPACKAGES:
        _link(root / name, package / name)
    return config
