"""Build hook for the cffi extension ``wake._rtp``; metadata lives in pyproject.toml."""

from setuptools import setup

setup(cffi_modules=["build_ffi.py:ffibuilder"])
