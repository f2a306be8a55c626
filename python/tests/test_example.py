"""The Python example (python/examples/runup.py, issue 30) runs as a user runs it: a run-up with
rub driven from a script, its matplotlib figure and its pyvista animation written."""

import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_the_runup_example_writes_its_figure_and_animation(tmp_path):
    r = subprocess.run(
        [sys.executable, str(ROOT / "python" / "examples" / "runup.py"), "--quick",
         "--frames", "12", "--out", str(tmp_path)],
        capture_output=True, text=True, cwd=ROOT,
    )
    assert r.returncode == 0, r.stderr
    assert "peak 1×" in r.stdout and " % of " in r.stderr
    import imageio.v3 as iio

    png = iio.imread(tmp_path / "runup.png")
    assert png.shape[0] > 400 and png.shape[1] > 400
    gif = iio.imread(tmp_path / "runup.gif", index=None)
    assert gif.shape[0] >= 10, gif.shape
    # rubsim's own outputs of the run beside them.
    assert (tmp_path / "run" / "summary.json").is_file()
    assert (tmp_path / "run" / "results.pvd").is_file()
