"""The version of tumble, in one module that imports nothing of the package, so
that any module can read it without importing the package root."""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

__all__ = ["__version__"]

try:
    __version__ = version("tumble")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"
