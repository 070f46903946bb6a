"""What produced a report: inputs by hash, certkit version and commit, library versions.

No wall-clock time is recorded, so the same inputs in the same environment give the
same bytes.
"""

from __future__ import annotations

import platform
from importlib import metadata

from packaging.requirements import InvalidRequirement, Requirement
from packaging.utils import canonicalize_name

from certkit.version import VERSION, git_commit

DEPENDENCIES = ("numpy", "numba", "scipy", "pandas", "pyarrow", "jinja2", "matplotlib", "weasyprint",
                "pydantic", "pint", "PyYAML")


def versions(names) -> dict:
    """Package name -> its installed version ("not installed" when absent)."""
    found = {}
    for name in names:
        try:
            found[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            found[name] = "not installed"
    return found


def provenance(inputs) -> dict:
    """Provenance record for results.json and the report."""
    return {
        "certkit_version": VERSION,
        "certkit_commit": git_commit(),
        "python": platform.python_version(),
        "dependencies": versions(DEPENDENCIES),
        "inputs": [{"file": item.name, "sha256": item.sha256, "bytes": item.size}
                   for item in inputs],
    }


def _requirement_names(distribution: str) -> list[str]:
    """Names of the packages ``distribution`` needs here: no extras, markers evaluated
    for this platform."""
    try:
        requires = metadata.requires(distribution) or []
    except metadata.PackageNotFoundError:
        return []
    names = []
    for text in requires:
        try:
            requirement = Requirement(text)
        except InvalidRequirement:   # a package's own malformed metadata: not certkit's
            continue
        if requirement.marker is None or requirement.marker.evaluate({"extra": ""}):
            names.append(requirement.name)
    return names


def environment() -> dict:
    """The software certkit runs on: its version and commit, Python, the platform, and
    every package it depends on, directly or not, with its version."""
    packages, pending = {}, _requirement_names("certkit") or list(DEPENDENCIES)
    while pending:
        name = pending.pop()
        key = canonicalize_name(name)
        if key in packages:
            continue
        try:
            packages[key] = metadata.version(name)
        except metadata.PackageNotFoundError:
            packages[key] = "not installed"
            continue
        pending.extend(_requirement_names(name))
    return {
        "certkit_version": VERSION,
        "certkit_commit": git_commit(),
        "python": f"{platform.python_implementation()} {platform.python_version()}",
        "platform": f"{platform.system()} {platform.machine()}",
        "packages": dict(sorted(packages.items())),
    }
