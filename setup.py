"""Build hook for the cffi extension ``wake._rtp``; metadata lives in pyproject.toml.

The compiled core is optional: without a working C compiler the build warns
and installs the pure-Python package, which runs on the float64 reference
backend (``WakeFilter`` picks it by default when ``wake._rtp`` is missing).
Set ``WAKE_REQUIRE_C=1`` to make a failed build an error instead.
"""

import os
import sys

from setuptools import setup
from setuptools.command.build_ext import build_ext

WARNING = """
********************************************************************************
WARNING: the fixed-point C core (wake._rtp) could not be built:
    {error}
wake is installed without it and runs on the float64 reference backend.
For the C core (the code firmware runs), install a C compiler (Debian/Ubuntu:
apt-get install gcc python3-dev) and reinstall: pip install .
********************************************************************************
"""


class OptionalBuildExt(build_ext):
    """build_ext that turns a failed compile into a warning (unless WAKE_REQUIRE_C=1)."""

    def run(self):
        try:
            super().run()
        except Exception as exc:  # no compiler at all: distutils raises before build_extension
            self._skip(exc)

    def build_extension(self, ext):
        try:
            super().build_extension(ext)
        except Exception as exc:  # CompileError, LinkError, a missing compiler binary
            self._skip(exc)

    def _skip(self, exc):
        if os.environ.get("WAKE_REQUIRE_C") == "1":
            raise exc
        sys.stderr.write(WARNING.format(error=str(exc).strip().splitlines()[-1] if str(exc).strip() else exc))


setup(cffi_modules=["build_ffi.py:ffibuilder"], cmdclass={"build_ext": OptionalBuildExt})
