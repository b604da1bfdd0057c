"""Numeric flags of ``dtcrit notebooks``, ``bench`` and ``impact`` (one argparse type,
``dtcrit.cli.flags.number``): zero where a positive value is needed, a negative value, NaN, an infinity,
an overflowing or non-numeric text is refused while parsing, one line naming the flag, exit status 2,
nothing on standard output, before any work; a library's range refusal is reported under the flag."""
from __future__ import annotations

import argparse

import pytest
from hypothesis import given
from hypothesis import strategies as st

from dtcrit.cli import build_parser, main
from dtcrit.cli.flags import number

BAD_ALWAYS = ["-1", "-0.5", "nan", "-nan", "inf", "-inf", "1e400", "-1e400", "abc", "", " ", "0x10"]
# (command prefix, flag, bad values beyond BAD_ALWAYS, a good value)
FLAGS = [
    (["notebooks", "--only", "none"], "--timeout", ["0", "1.5", "86401", "1e3"], "30"),
    (["bench", "--quick"], "--scenes", ["0", "2.5", "10000001"], "1000"),
    (["impact", "--integrator", "leapfrog", "--omega-dt", "1"], "--zeta", [], "0"),
    (["impact", "--integrator", "leapfrog"], "--omega-dt", ["0", "-0.0"], "1.2"),
    (["impact", "--integrator", "leapfrog", "--omega-dt", "1"], "--step", ["0"], "0.1"),
    (["impact", "--integrator", "leapfrog", "--omega-dt", "1"], "--phases", ["0", "1.5"], "8"),
    (["impact", "--integrator", "leapfrog", "--omega-dt", "1"], "--energy-threshold", ["0"], "0.05"),
]
CASES = [(pre, flag, bad) for pre, flag, extra, _ in FLAGS for bad in BAD_ALWAYS + extra]


@pytest.mark.parametrize("prefix,flag,bad", CASES, ids=lambda v: v if isinstance(v, str) else None)
def test_a_bad_value_is_refused_in_one_line_naming_the_flag(prefix, flag, bad, capsys):
    with pytest.raises(SystemExit) as exc:
        main([*prefix, f"{flag}={bad}"])
    assert exc.value.code == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1 and f"argument {flag}: must be a " in err, err


def test_the_issue_case_timeout_zero(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["notebooks", "--timeout", "0"])
    assert exc.value.code == 2
    assert "--timeout: must be a positive number of seconds" in capsys.readouterr().err


@pytest.mark.parametrize("prefix,flag,good", [(p, f, g) for p, f, _, g in FLAGS])
def test_a_good_value_parses_to_its_number(prefix, flag, good):
    args = build_parser().parse_args([*prefix, flag, good])
    assert getattr(args, flag[2:].replace("-", "_")) == (int(good) if flag in ("--timeout", "--scenes", "--phases")
                                                        else float(good))


@pytest.mark.parametrize("argv,message", [
    (["impact", "--integrator", "leapfrog", "--omega-dt", "1", "--phases", "100000"], "dtcrit: --phases: must be an integer in [1, 4096]"),
    (["impact", "--integrator", "leapfrog", "--omega-dt", "5000"], "dtcrit: --omega-dt: must lie in"),
    (["impact", "--integrator", "leapfrog", "--energy-threshold", "2"], "dtcrit: --energy-threshold: must lie in (0, 1)"),
    (["impact", "--integrator", "leapfrg", "--omega-dt", "1"], "dtcrit: --integrator: unknown integrator 'leapfrg'"),
    (["bench", "--quick", "--scenes", "5"], "dtcrit: --scenes: must be at least"),
])
def test_a_library_range_refusal_names_the_flag(argv, message, capsys):
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1 and err.startswith(message), err


@given(st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**30, 10**30)))
def test_the_type_accepts_exactly_the_finite_values_in_range(x):
    text = repr(x)
    for kind, positive, maximum in ((float, True, None), (float, False, None), (int, True, 10**6)):
        try:
            got = number(kind, positive=positive, maximum=maximum)(text)
        except argparse.ArgumentTypeError:
            got = None
        value = float(x)
        finite_kind = isinstance(x, int) if kind is int else value == value and abs(value) != float("inf")
        ok = finite_kind and (value > 0 if positive else value >= 0) and (maximum is None or value <= maximum)
        assert (got is not None) == ok, (kind, positive, maximum, text, got)
        if ok:
            assert got == (int(text) if kind is int else float(text))
