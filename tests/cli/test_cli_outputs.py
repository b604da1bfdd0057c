"""Commands that write files check, before any work, that they can: one line and exit 2 (never a traceback
after minutes of work, nothing created); out-of-range numbers are refused the same way."""
from __future__ import annotations

import pytest

from dtcrit.cli import main

BAD_DIR = "/dev/null/cannot-be-a-folder"


@pytest.mark.parametrize("argv,key", [
    (["figures", "--out", BAD_DIR], "--out: cannot write"),
    (["bench", "--quick", "--out", BAD_DIR], "--out: cannot write"),
    (["impact", "--integrator", "leapfrog", "--zeta", "0.1", "--out", BAD_DIR], "--out: cannot write"),
    (["notebooks", "--out", BAD_DIR], "--out: cannot write"),
    (["packing", "--lattice", "sc", "--cells", "2", "--kn", "1", "--ks", "1", "--write-dump", BAD_DIR + "/p.dump"],
     "--write-dump: cannot write"),
    (["impact", "--integrator", "leapfrog", "--zeta", "1e308"], "zeta: damping ratio 1e+308 is above"),
])
def test_refused_before_any_work(argv, key, capsys):
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1 and key in err and "Traceback" not in err, err


def test_an_existing_file_is_not_a_folder(tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    assert main(["figures", "--out", str(f)]) == 2
    assert "exists and is not a folder" in capsys.readouterr().err
