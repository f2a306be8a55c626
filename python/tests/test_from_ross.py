"""`rubsim.from_ross` of ROSS's own rotor objects (issue 30), in whichever ROSS the venv has:
ROSS 2.3 in the project's .venv (Python 3.11), ROSS 3.0 in .venv-ross3 (Python 3.12, the same
abi3 wheel), both run by scripts/test-slow.sh. The scene is the one `import-ross` makes of the
saved file, and the modes at 0 and 1000 rad/s are ROSS's dense `run_modal` (scipy's eig: every
mode to round-off) to 1e-8 in ω_d and ζ, each ROSS mode matched to rubsim's nearest in ω_d among
those with ζ < 0.5.
"""

import os
import pathlib
import subprocess

import numpy as np
import pytest

import rubsim

pytestmark = pytest.mark.slow
if os.environ.get("RUBSIM_REQUIRE_ROSS") == "1":
    import ross as rs
else:
    rs = pytest.importorskip("ross")

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = os.environ.get("RUBSIM_BIN", str(ROOT / "target" / "release" / "rubsim"))
MAJOR = int(rs.__version__.split(".")[0])


@pytest.mark.parametrize("name", ["rotor_example", "rotor_example_with_damping"])
def test_from_ross_gives_rosss_rotor_and_modes(tmp_path, name):
    rotor = getattr(rs, name)()
    scene = rubsim.from_ross(rotor)
    # The version is detected and named in the scene.
    assert f"# Format: ROSS {MAJOR}" in scene.source, scene.source[:400]
    # The same rotor as the command line's import of the saved file.
    saved = tmp_path / "saved.toml"
    rotor.save(str(saved))
    out = tmp_path / "scene.toml"
    r = subprocess.run([BIN, "import-ross", str(saved), "--out", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert scene.to_dict()["rotor"] == rubsim.Scene(out).to_dict()["rotor"]
    worst = [0.0, 0.0]
    for speed in (0.0, 1000.0):
        want = rotor.run_modal(speed, num_modes=400, sparse=False)
        got = scene.modal(speed, modes=400)
        keep = got.damping_ratio < 0.5
        wd, zeta = got.omega_d[keep], got.damping_ratio[keep]
        n = 0
        for w, z in zip(want.wd, want.damping_ratio):
            if z >= 0.5 or w < 1e-3:
                continue
            k = int(np.argmin(np.abs(wd - w)))
            worst[0] = max(worst[0], abs(wd[k] / w - 1))
            worst[1] = max(worst[1], abs(zeta[k] - z) / max(abs(z), 1e-3))
            n += 1
            if n == 12:
                break
        assert n == 12
    print(f"ROSS {rs.__version__} {name}: ω_d {worst[0]:.2e}, ζ {worst[1]:.2e}")
    assert worst[0] < 1e-8 and worst[1] < 1e-8, worst
