"""``dtcrit codegen SCENE --lang ...`` end to end: deterministic output, written files that compile
and run, bad input as one line with exit status 2."""
import ctypes
import subprocess
import sys

import pytest
from support.codegen import C_FLAGS, CC, fortran_library
from support.precision import ulps

from dtcrit.cli import main
from dtcrit.scenes.laws import resolve_pair
from support.paths import REPO_ROOT as ROOT

SCENE = ROOT / "examples" / "damped_ellipsoids.toml"


def test_module_entry_point_matches_in_process_output(capsys):
    p = subprocess.run([sys.executable, "-m", "dtcrit", "codegen", str(SCENE), "--lang", "c"], cwd=ROOT,
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert main(["codegen", str(SCENE), "--lang", "c"]) == 0
    assert capsys.readouterr().out == p.stdout
    assert "double dtcrit_dt_crit(double m, double I_xx, double r, double kn, double ks, double cn, double cs)" in p.stdout


def test_written_c_file_compiles_and_matches_dtcrit_step(tmp_path, capsys):
    out = tmp_path / "dt.c"
    assert main(["codegen", str(SCENE), "--lang", "c", "--name", "contact_dt", "--out", str(out)]) == 0
    lib = tmp_path / "dt.so"
    subprocess.run([CC, *C_FLAGS, "-O2", "-shared", "-fPIC", "-o", str(lib), str(out), "-lm"], check=True)
    f = ctypes.CDLL(str(lib)).contact_dt
    f.restype = ctypes.c_double
    f.argtypes = [ctypes.c_double] * 7
    from dtcrit.scenes.scene import load_scene
    from dtcrit.scenes.timestep import critical_step

    s = load_scene(SCENE)
    sh, pc = s.particle(1).shape, resolve_pair(s, 1, 1)
    got = f(sh.mass, sh.inertia[0], sh.max_arm, pc.kn, pc.ks, pc.cn, pc.cs)
    verified = critical_step(s).dt_isolated  # the kernel is one contact's step
    # the arm-based A of the kernel (Eq. (26) with the largest arm) bounds a_bound: a smaller or equal step
    assert 0 < got <= verified
    capsys.readouterr()


def _bound(lib, name, nargs):
    f = getattr(ctypes.CDLL(str(lib)), name)
    f.restype = ctypes.c_double
    f.argtypes = [ctypes.c_double] * nargs
    return f


@pytest.mark.parametrize("scene", ["damped_ellipsoids", "mixed_pair", "glass_spheres_hertz"])
def test_written_fortran_file_compiles_and_matches_the_c(scene, tmp_path, capsys):
    """The Fortran module of a scene, written with --out and a 48-character name (the longest
    allowed), compiles under the strict flags and its bind(C) function gives the C's values."""
    path, name = ROOT / "examples" / f"{scene}.toml", "k" * 48
    for lang, suffix in (("c", ".c"), ("fortran", ".f90")):
        assert main(["codegen", str(path), "--lang", lang, "--name", name, "--out", str(tmp_path / f"dt{suffix}")]) == 0
    capsys.readouterr()
    f_lib = fortran_library((tmp_path / "dt.f90").read_text())  # skips with the stated reason without gfortran
    c_lib = tmp_path / "dt.so"
    subprocess.run([CC, *C_FLAGS, "-O2", "-shared", "-fPIC", "-o", str(c_lib), str(tmp_path / "dt.c"), "-lm"], check=True)
    from dtcrit.codegen import build_kernel, structure_of_scene
    from dtcrit.scenes.scene import load_scene

    nargs = len(build_kernel(structure_of_scene(load_scene(path))).arguments)
    f_f, f_c = _bound(f_lib, name, nargs), _bound(c_lib, name, nargs)
    for i in range(20):  # positive values over ten decades, mixed across the arguments
        v = [10.0 ** (((3 * i + 7 * j) % 11) - 5) for j in range(nargs)]
        assert ulps(f_f(*v), f_c(*v)) <= 1, v


@pytest.mark.parametrize("lang", ["c", "numpy", "fortran"])
def test_every_language_is_emitted(lang, capsys):
    assert main(["codegen", str(ROOT / "examples" / "glass_spheres_hertz.toml"), "--lang", lang]) == 0
    text = capsys.readouterr().out
    assert "A_s = 7/m" in text and "Derivation hash" in text


def test_bad_input(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('integrator = "leapfrog"\n')
    assert main(["codegen", str(bad), "--lang", "c"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{bad}:particle: missing") and len(err.splitlines()) == 1
    assert main(["codegen", str(SCENE), "--lang", "c", "--name", "1bad name"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("dtcrit: --name: must be an identifier") and len(err.splitlines()) == 1
    for taken in ("kn", "KN"):  # an argument (any case, as in Fortran)
        assert main(["codegen", str(SCENE), "--lang", "fortran", "--name", taken]) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"dtcrit: --name: '{taken}' is already a name in the emitted code") and len(err.splitlines()) == 1
    for reserved in ("sqrt", "while", "range", "Exp", "main"):  # a function called, a keyword, a Python built-in
        assert main(["codegen", str(SCENE), "--lang", "fortran", "--name", reserved]) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"dtcrit: --name: '{reserved}' is a keyword or a name C, Fortran or Python already gives") \
            and len(err.splitlines()) == 1
    undamped_fe = tmp_path / "fe.toml"
    undamped_fe.write_text((ROOT / "examples" / "paper_ellipsoids.toml").read_text().replace("velocity-verlet", "forward-euler"))
    assert main(["codegen", str(undamped_fe), "--lang", "c"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{undamped_fe}:integrator: 'forward-euler' has no stable step") and len(err.splitlines()) == 1
    with pytest.raises(SystemExit) as exc:
        main(["codegen", str(SCENE), "--lang", "cobol"])
    assert exc.value.code == 2


def test_numpy_output_is_vectorised(tmp_path, capsys):
    assert main(["codegen", str(SCENE), "--lang", "numpy", "--out", str(tmp_path / "k.py")]) == 0
    capsys.readouterr()
    import importlib.util

    import numpy as np

    spec = importlib.util.spec_from_file_location("k_vec", tmp_path / "k.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    m = np.logspace(-3, 3, 7)
    out = mod.dtcrit_dt_crit(m, 0.2 * m, 1.0, 1e6, 5e5, 10.0, 5.0)
    assert out.shape == (7,)
    single = [float(mod.dtcrit_dt_crit(x, 0.2 * x, 1.0, 1e6, 5e5, 10.0, 5.0)) for x in m]
    assert all(ulps(a, b) == 0 for a, b in zip(out, single))


@pytest.mark.parametrize("scene", ["rolling_resistance.toml", "bonded_pair.toml"])
def test_scenes_whose_springs_the_kernel_lacks_are_refused(scene, capsys, tmp_path):
    """The emitted kernel carries normal and tangential springs only: a rolling or bond scene would get a
    step above its own, so codegen refuses it in one line, writing nothing."""

    from dtcrit.cli import main

    out = tmp_path / "k.c"
    path = ROOT / "examples" / scene
    assert main(["codegen", str(path), "--lang", "c", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "does not carry" in err and not out.exists()
