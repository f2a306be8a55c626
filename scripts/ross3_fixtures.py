"""ROSS 3 fixtures for `rubsim import-ross` (issue 30): rotors saved by ROSS 3's `Rotor.save` and
ROSS 3's own modal results for them, committed under tests/data/ross/ross3/ so that the tests
(tests/suite/import_ross.rs, `ross3_*`) need no ROSS 3 — which needs Python ≥ 3.12, while the
test machines' ROSS (scripts/setup.sh) is 2.3.0 for Python 3.11.

Rerun (writes the files again; the saved rotors and the numbers change only with ROSS):

    PYENV_VERSION=3.12.1 python -m venv /tmp/venv312
    /tmp/venv312/bin/pip install 'ross-rotordynamics==3.0.0'
    /tmp/venv312/bin/python scripts/ross3_fixtures.py

Rotors:
- rotor_example_with_damping: ROSS's own, Rayleigh α = 8.0501 1/s, β = 1e-5 s on the rotor
  (ROSS 3 keeps them under [parameters]; 2.3 kept them on the shaft elements), bearings with
  cxx/cyy; saved as TOML and JSON.
- both_damping: rotor_example (6-DOF, free axial and torsion) with damped bearings, rotor-level
  α, β and other element-level α, β, which ROSS 3 ignores beside the rotor's (it warns "More
  than one type of damping was provided"). (A point mass is not tried: ROSS gives each one 3
  DOFs of its own, which a point mass on a shaft node leaves massless — M is singular.)

Modal results: `run_modal(speed, num_modes=400, sparse=False)` (scipy's dense eig: every mode
to round-off, where ARPACK's ζ moves by ~1e-6 between runs), the first 12 modes with ζ < 0.5,
their ω_d (rad/s) and ζ at 0 and 1000 rad/s, in modal_reference.json.
"""

import json
import os
import warnings

import numpy as np
import ross as rs

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "tests", "data", "ross", "ross3")
SPEEDS = [0.0, 1000.0]
MODES = 12


def both_damping():
    base = rs.rotor_example()
    steel = base.shaft_elements[0].material
    shaft = [
        rs.ShaftElement(0.25, 0.0, 0.05, material=steel, alpha=3.0, beta=2e-5) for _ in range(6)
    ]
    bearings = [
        rs.BearingElement(n=0, kxx=1e6, kyy=0.8e6, cxx=120.0, cyy=80.0),
        rs.BearingElement(n=6, kxx=1e6, kyy=0.8e6, cxx=150.0, cyy=60.0),
    ]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rotor = rs.Rotor(shaft, base.disk_elements, bearings, alpha=1.5, beta=4e-5)
    assert any("More than one type of damping" in str(w.message) for w in caught), caught
    return rotor


def main():
    os.makedirs(OUT, exist_ok=True)
    rotors = {
        "rotor_example_with_damping": rs.rotor_example_with_damping(),
        "both_damping": both_damping(),
    }
    rotors["rotor_example_with_damping"].save(os.path.join(OUT, "rotor_example_with_damping.json"))
    reference = {"ross_version": rs.__version__, "speeds": SPEEDS, "rotors": {}}
    for name, rotor in rotors.items():
        rotor.save(os.path.join(OUT, f"{name}.toml"))
        per_speed = {}
        for speed in SPEEDS:
            modal = rotor.run_modal(speed, num_modes=400, sparse=False)
            # The dense solver lists first the overdamped pairs (ζ ≈ 1) that the spin makes
            # complex with a small ω_d, and the free axial DOF's mode of C = α M (λ = −α):
            # left out, as tests/post/test_ross.py does.
            keep = np.asarray(modal.damping_ratio) < 0.5
            per_speed[repr(speed)] = {
                "wd": [float(x) for x in np.asarray(modal.wd)[keep][:MODES]],
                "damping_ratio": [float(x) for x in np.asarray(modal.damping_ratio)[keep][:MODES]],
            }
        reference["rotors"][name] = per_speed
    with open(os.path.join(OUT, "modal_reference.json"), "w") as f:
        json.dump(reference, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
