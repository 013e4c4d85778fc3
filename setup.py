"""Build step for the one compiled part: the row-by-row assembly (flexarm/fe/_rows.c).

Everything else is in pyproject.toml.  The extension is optional: without a C compiler
the install still succeeds and the assembly falls back to its NumPy path.
"""

from setuptools import Extension, setup

setup(
    ext_modules=[
        Extension("flexarm.fe._rows", ["flexarm/fe/_rows.c"], optional=True,
                  extra_compile_args=["-O3"]),
    ],
)
