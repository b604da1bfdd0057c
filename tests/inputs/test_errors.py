"""The error hierarchy of dtcrit.errors: one base, bad input (with its location), a solver that did
not converge (with its bracket), misuse of the API; each also the built-in error Python users expect.
"""
import pickle

import numpy as np
import pytest

from dtcrit.errors import DtcritError, InputError, Location, MisuseError, NotConvergedError


def test_each_error_is_a_dtcrit_error_and_the_matching_builtin():
    assert issubclass(InputError, DtcritError) and issubclass(InputError, ValueError)
    assert issubclass(NotConvergedError, DtcritError) and issubclass(NotConvergedError, ArithmeticError)
    assert issubclass(MisuseError, DtcritError) and issubclass(MisuseError, TypeError)
    assert not issubclass(InputError, TypeError) and not issubclass(MisuseError, ValueError)


def test_the_key_reason_form_keeps_its_key_and_message():
    exc = InputError("contact.kn", "must be positive (got -1)")
    assert exc.key == "contact.kn" and exc.reason == "must be positive (got -1)"
    assert str(exc) == "contact.kn: must be positive (got -1)"
    assert exc.location == Location(None, None, "contact.kn")


@pytest.mark.parametrize("source, line, key, text", [
    ("a.dump", 7, None, "a.dump:7"),
    ("b.json", None, "bodies[3].id", "b.json: bodies[3].id"),
    (None, 12, None, "line 12"),
    ("c.txt", None, None, "c.txt"),
    ("d.txt", 4, "kn", "d.txt:4: kn"),
])
def test_a_location_prints_source_line_and_key(source, line, key, text):
    exc = InputError(key, "bad", source=source, line=line)
    assert exc.location == Location(source, line, key)
    assert exc.key == text and str(exc) == f"{text}: bad"
    assert InputError.at(Location(source, line, key), "bad").location == exc.location


def test_an_error_is_placed_in_its_file_afterwards():
    exc = InputError(None, "'x' is not a number", line=10).within("p.dump")
    assert exc.location == Location("p.dump", 10, None) and str(exc) == "p.dump:10: 'x' is not a number"


def test_an_input_error_survives_pickling_with_its_location():
    exc = InputError("bodies[0].mass", "must be positive, found -1", source="e.json")
    back = pickle.loads(pickle.dumps(exc))
    assert type(back) is InputError and back.location == exc.location and str(back) == str(exc)


def test_not_converged_carries_its_bracket():
    exc = NotConvergedError("dt_crit [s]", 1e-6, 2e-6, "ARPACK eigsh", "300 iterations")
    assert exc.bracket == (1e-6, 2e-6) and exc.solver == "ARPACK eigsh"
    assert str(exc) == "ARPACK eigsh did not converge (300 iterations); dt_crit [s] lies in [1e-06, 2e-06]"


def test_the_retired_rotation_call_is_misuse():
    from dtcrit.bodies import Sphere
    from dtcrit.bodies.contact import coefficient_matrix

    s = Sphere(1.0, density=1000.0)
    with pytest.raises(MisuseError) as caught:
        coefficient_matrix(s, s, np.array([1.0, 0, 0]), np.array([-1.0, 0, 0]), np.eye(3), np.eye(3))
    assert isinstance(caught.value, TypeError)
