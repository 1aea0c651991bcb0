"""The kernels compiled at build time cover every command: after them, nothing compiles.

The package's build compiles :data:`stepframe.core.kernel_cache.ENTRY_POINTS` into the cache it
ships (setup.py). Here the same compilation goes into an empty ``NUMBA_CACHE_DIR`` (done once
for the suite by tests/conftest.py, which keeps it apart from the cache the other tests run on;
compiled here when it could not), then a command of each kernel family runs on a copy of that
cache with the compile notice on: a kernel or a signature missing from the list would compile
there, and say so on stderr.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import stepframe
from stepframe.core import kernel_cache

DATA = Path(__file__).parents[1] / "data" / "peer_nga_west2"
RECORD_1 = DATA / "RSN8883_14383980_13849090.AT2"
RECORD_2 = DATA / "RSN8883_14383980_13849360.AT2"
FRAME = Path(stepframe.__file__).parent / "workflows" / "frames" / "example-4.toml"
SITE = ("--fp-hz", "7.43", "--fs-hz", "3.12", "--fr-hz", "1.11", "--xi-p", "0.096")
BLOCK = ("--block", "0.25,1.0", "--omega-rad-s", "16")


def _commands(out: Path) -> list[list[str]]:
    """One command of each kernel family, on the small real records of tests/data."""
    record = [str(RECORD_1)]
    return [
        ["structure", "simulate", "--frame", str(FRAME), *record, "--scale", "6", "--json",
         "--plot", str(out / "response.png")],
        ["records", "spectrum", *record, str(RECORD_2), "--periods-s", "0.1,1.0", "--json"],
        ["stochastic", "fit", *record, "--spectrum", "wavelet", "--out", str(out / "fit.nc"),
         "--json"],
        ["stochastic", "amplify", *SITE, "--xi-r", "0.655", "--t-max-s", "5", "--t-dur-s", "20",
         "--f0-hz", "2", "--json"],
        ["stochastic", "amplify", "--record", *record, "--frame", str(FRAME), "--json"],
        ["structure", "harmonic", *BLOCK, "--amplitude-g", "0.3", "--periods", "20", "--orbit",
         "1", "--json"],
        ["structure", "bifurcation", *BLOCK, "--amplitudes-g", "0.1,0.3,3", "--initial", "2",
         "--periods", "10", "--jobs", "1", "--json"],
        ["structure", "ida", "--block", "0.25,1.0", "--pulse", "cosine", "--omega-rad-s", "10.8",
         "--resolution-g", "0.01", "--json"],
        ["select", "--frame", str(FRAME), str(DATA), "-n", "1", "--confirm", "--jobs", "1",
         "-o", str(out / "picks"), "--json"],
    ]  # fmt: skip


# The library's simulators that no command runs (the A-frame, the rocking block).
_LIBRARY = """
import numpy as np
from stepframe.structure.aframe_hysteretic import simulate_aframe
from stepframe.structure.frame import AFrame, RockingBlock
from stepframe.structure.rocking_block import simulate_block
ag = 3.0 * np.sin(np.linspace(0.0, 20.0, 401))
frame = AFrame(omega_1_rad_s=6.0, omega_2_rad_s=0.7, p_1=1.1, p_2=1.2, gamma_1_m_s2=0.15,
               xi_1=0.05, theta_rad=0.2, x_c_m=0.04, c_r=0.9, x_cap_m=0.6)
simulate_aframe(frame, ag, 0.01)
simulate_block(RockingBlock(half_width_m=0.25, half_height_m=1.0), ag, 0.01)
"""

# One small kernel of the list, to see the notice of a compilation (a second or so; the
# library's simulators above take ten).
_ONE_KERNEL = """
import numpy as np
from stepframe.stochastic._wavelet_kernel import band_powers
band_powers(np.zeros((1, 2), dtype=np.complex128), 1, 1, np.ones(1))
"""

_DRIVER = """
import sys
from stepframe.cli import main
for argv in {commands!r}:
    print("stepframe-test: " + " ".join(argv[:2]), file=sys.stderr, flush=True)
    status = main(argv)
    if status != 0:
        raise SystemExit(f"{{argv[:2]}} exited {{status}}")
print("stepframe-test: library", file=sys.stderr, flush=True)
{library}
"""


@pytest.mark.slow
def test_no_command_compiles_after_the_entry_points(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env.update(NUMBA_CACHE_DIR=str(tmp_path / "cache"), STEPFRAME_COMPILE_NOTICE="1")
    suite_build = os.environ.get("STEPFRAME_TEST_BUILT_KERNELS")  # tests/conftest.py's
    if suite_build:
        shutil.copytree(Path(suite_build) / "cache", tmp_path / "cache")
        build_log = (Path(suite_build) / "build.log").read_text()
    else:
        built = subprocess.run(
            [sys.executable, "-m", "stepframe.core.kernel_cache", "--jobs", "2"],
            capture_output=True, text=True, env=env, timeout=900, cwd=tmp_path,
        )  # fmt: skip
        assert built.returncode == 0, built.stderr
        build_log = built.stderr
    assert f"{len(kernel_cache.ENTRY_POINTS)} numba kernels compiled" in build_log
    # Every entry point left its own index in the cache.
    indexes = {p.name.split("-")[0] for p in (tmp_path / "cache").rglob("*.nbi")}
    for entry in kernel_cache.ENTRY_POINTS:
        assert f"{entry.module.rsplit('.', 1)[1]}.{entry.function}" in indexes

    driver = _DRIVER.format(commands=_commands(tmp_path), library=_LIBRARY)
    ran = subprocess.run(
        [sys.executable, "-c", driver],
        capture_output=True, text=True, env=env, timeout=900, cwd=tmp_path,
    )  # fmt: skip
    assert ran.returncode == 0, ran.stderr[-3000:]
    lines = [line for line in ran.stderr.splitlines() if "compiling" in line]
    assert lines == [], "\n".join(ran.stderr.splitlines()[-40:])
    # The notice is really on in these runs: with an empty cache the same driver says so on
    # its first compilation (one small kernel: what is tested is the notice, not the list).
    fresh = dict(env, NUMBA_CACHE_DIR=str(tmp_path / "empty"))
    first = subprocess.run(
        [sys.executable, "-c", _DRIVER.format(commands=[], library=_ONE_KERNEL)],
        capture_output=True, text=True, env=fresh, timeout=900, cwd=tmp_path,
    )  # fmt: skip
    assert first.returncode == 0, first.stderr[-3000:]
    assert "compiling numba kernels once" in first.stderr


@pytest.mark.parametrize(
    ("spelling", "expected"),
    [
        ("f8", "float64"),
        ("i1[:]", "array(int8, 1d, C)"),
        ("f8[:, :, :]", "array(float64, 3d, C)"),
        ("ro f8[:]", "readonly array(float64, 1d, C)"),
        ("c16[:]", "array(complex128, 1d, C)"),
        ("b1", "bool"),
        ("f4[:, :]", "array(float32, 2d, C)"),
    ],
)
def test_spellings_are_numba_types(spelling: str, expected: str) -> None:
    assert str(kernel_cache.numba_type(spelling)) == expected


@pytest.mark.parametrize("spelling", ["f2", "ro f8", "float64[:]"])
def test_an_unknown_spelling_is_an_error(spelling: str) -> None:
    with pytest.raises(ValueError, match=r"expected|only an array"):
        kernel_cache.numba_type(spelling)


def test_jobs_must_be_positive(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as stop:
        kernel_cache.main(["--jobs", "0"])
    assert stop.value.code == 2
    assert "expected a positive number" in capsys.readouterr().err
