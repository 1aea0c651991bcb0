"""The package's build: setuptools as configured in pyproject.toml, plus the compiled kernels.

``build_py`` copies the sources into the build tree as usual, then runs
``python -m stepframe.core.kernel_cache`` on that tree, so numba's cache of every kernel
(``__pycache__/*.nbi``, ``*.nbc`` beside each source) goes into the wheel and no command compiles
on its first run (the reasons and the limits are in that module's docstring). Set
``STEPFRAME_PRECOMPILE=0`` to build without it (the kernels then compile on first use); an editable
install never runs it (run the module by hand there if wanted).
"""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys

from setuptools import setup
from setuptools.command.build_py import build_py


class BuildWithKernels(build_py):
    """``build_py``, then the kernels compiled into the build tree's numba cache."""

    def run(self) -> None:
        super().run()
        precompile = os.environ.get("STEPFRAME_PRECOMPILE", "1")
        if precompile not in ("0", "1"):
            raise SystemExit(f"STEPFRAME_PRECOMPILE={precompile!r}: expected 0 (skip) or 1")
        if getattr(self, "editable_mode", False) or precompile == "0":
            return
        if importlib.util.find_spec("numba") is None:
            raise SystemExit(
                "stepframe's build compiles its numba kernels and needs numba in the build "
                "environment (pip puts it there; with --no-build-isolation install numba first), "
                "or STEPFRAME_PRECOMPILE=0 to build without them"
            )
        # The child sees what this process sees: the built tree first, then this interpreter's
        # path (pip's isolated build environment, where numba is, is on it, not in the venv).
        path = [os.path.abspath(self.build_lib), *(p for p in sys.path if p)]
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(path))
        # numba's own cache folder would take the cache away from the sources it ships with, and
        # with the JIT off there is nothing to compile (other NUMBA_ settings, as a CPU name for
        # a portable wheel, are the builder's to choose).
        env.pop("NUMBA_CACHE_DIR", None)
        env.pop("NUMBA_DISABLE_JIT", None)
        print(
            "stepframe: compiling the numba kernels into the package (STEPFRAME_PRECOMPILE=0 "
            "skips this)",
            file=sys.stderr,
            flush=True,
        )
        subprocess.run(
            [sys.executable, "-m", "stepframe.core.kernel_cache"],
            env=env,
            cwd=self.build_lib,
            check=True,
        )


setup(cmdclass={"build_py": BuildWithKernels})
