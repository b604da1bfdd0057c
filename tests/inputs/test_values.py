"""The one check of each kind of value (dtcrit.inputs): the messages users read, as literals."""
import math

import numpy as np
import pytest

from dtcrit.errors import InputError
from dtcrit.inputs import arrays, keys, text, values


def _reason(call) -> tuple[str, str]:
    with pytest.raises(InputError) as caught:
        call()
    return caught.value.key, caught.value.reason


@pytest.mark.parametrize("value, kwargs, reason", [
    ("1", {}, "must be a number (got a string: '1')"),
    (True, {}, "must be a number (got a boolean: True)"),
    (10**400, {}, "must be a finite number (got an integer with 401 digits)"),
    (math.inf, {}, "must be finite (got inf)"),
    (0, {}, "must be positive (got 0)"),
    (-1.5, {"allow_zero": True}, "must be non-negative (got -1.5)"),
    (-1.0, {"lo": -1.0}, "must be greater than -1 (got -1)"),
    (0.5, {"lo": -1.0, "hi": 0.5, "hi_open": True}, "must be less than 0.5 (got 0.5)"),
    (2.0, {"hi": 1.0}, "must be at most 1 (got 2)"),
])
def test_number_refuses_with_one_line(value, kwargs, reason):
    assert _reason(lambda: values.number("k", value, **kwargs)) == ("k", reason)


def test_number_accepts_bounds():
    assert values.number("k", 0, allow_zero=True) == 0.0
    assert values.number("k", -0.5, lo=-1.0, hi=0.5) == -0.5


def test_choice_suggests_the_nearest():
    assert values.choice("s", "Sphere", ("sphere", "box"), "shape") == "sphere"
    assert _reason(lambda: values.choice("s", "spher", ("sphere", "box"), "shape")) == (
        "s", "unknown shape 'spher' (did you mean 'sphere'?); choose one of sphere, box")


def test_engine_style_numbers_and_ids():
    assert values.finite("w", -0.0) == 0.0 and math.copysign(1.0, values.finite("w", -0.0)) == 1.0
    assert values.finite("w", None, allow_none=True) is None
    assert _reason(lambda: values.finite("w", 0, positive=True)) == ("w", "must be positive, found 0")
    assert _reason(lambda: values.finite("w", "a")) == ("w", "expected a finite number, found 'a'")
    assert values.whole("w", 3.0) == 3
    assert _reason(lambda: values.whole("w", 2**63)) == ("w", f"expected an integer id, found {2**63}")
    assert _reason(lambda: values.integer_id("w", 3.0)) == ("w", "expected an integer id, found 3.0")
    assert _reason(lambda: values.stiffness("w", -1)) == ("w", "expected a finite stiffness >= 0 [N/m], found -1")
    assert _reason(lambda: values.boolean("w", 1)) == ("w", "must be true or false (got 1)")


def test_vectors_and_rows_count_entries_as_their_format_does():
    assert _reason(lambda: arrays.vector("a", [1, 2], 3)) == ("a", "must have 3 entries (got 2)")
    assert _reason(lambda: arrays.vector("a", [1, 0, 2], 3)) == ("a[2]", "must be positive (got 0)")
    assert _reason(lambda: arrays.triple("p", [0.0, "x", 1.0])) == ("p[1]", "expected a finite number, found 'x'")
    assert _reason(lambda: arrays.vertices("v", [[0, 0, 0]] * 3)) == ("v", "needs at least 4 points (got 3)")
    assert _reason(lambda: arrays.clump_spheres("s", [[0, 0, 0, -1]])) == ("s[1][4]", "the radius must be positive (got -1)")
    assert np.array_equal(arrays.rows(lambda k: f"r[{k}]", [None, [1, 2]], 2, [0, 0]), [[0, 0], [1, 2]])
    assert _reason(lambda: arrays.rows(lambda k: f"r[{k}]", [[1, 2], [1, math.nan]], 2)) == (
        "r[1]", "expected an array of 2 finite numbers, found [1, nan]")
    assert _reason(lambda: arrays.booleans("p", [True, 1, False], 3)) == ("p", "expected three booleans, found [True, 1, False]")


def test_keys_name_the_key_and_the_nearest_valid_one():
    assert _reason(lambda: keys.check_keys("contact.", {"kn": 1, "kss": 2}, ("kn", "ks"), ("kn", "ks"), "here")) == (
        "contact.kss", "unknown key (did you mean 'ks'?); valid keys here: kn, ks")
    assert _reason(lambda: keys.check_keys("t.", {"a b": 1}, ("kn",), (), "here")) == (
        't."a b"', "unknown key; valid keys here: kn")
    assert _reason(lambda: keys.required("contact.", {}, "kn", "the stiffness")) == ("contact.kn", "missing: the stiffness")
    assert _reason(lambda: keys.known_keys("f: bodies[0]", {"idd": 1}, ("id",))) == (
        "f: bodies[0].idd", "unknown key; valid keys here: id")


def test_text_is_one_short_line():
    assert text.short("a\n  b") == "'a\\n b'"  # repr escapes the newline; runs of blanks become one
    assert text.short("x" * 100, 10) == "'xxxxxx..."
    assert text.show(1.5) == "1.5" and text.type_name({}) == "a table"
