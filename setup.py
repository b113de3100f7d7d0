"""Package layout: the repository keeps ``geometry/``, ``importers/`` and ``solver/`` at its top,
and they install as ``ibfem.geometry``, ``ibfem.importers`` and ``ibfem.solver`` under the one
``ibfem`` namespace (nothing generic is installed at top level). Metadata lives in pyproject.toml."""

from setuptools import find_packages, setup

SUBPACKAGES = ("geometry", "importers", "solver")

packages = ["ibfem"]
package_dir = {"ibfem": "ibfem"}
for name in SUBPACKAGES:
    package_dir[f"ibfem.{name}"] = name
    packages += [f"ibfem.{name}"] + [f"ibfem.{name}.{sub}" for sub in find_packages(name)]

setup(packages=packages, package_dir=package_dir, package_data={"ibfem": ["py.typed"]})
