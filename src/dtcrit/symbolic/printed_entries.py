"""The entries of Peng et al. (2020), Eqs. (22)-(24) and (50)-(52), as printed, read and compared with
the derived accelerations (the scoring of the Figure 2 candidates is in ``dtcrit.symbolic.candidate_scores``).
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from dtcrit.symbolic.tip_configurations import P1, P2

# ----------------------------------------------------------------------------------------------
# The printed Eqs (22)-(24) and (50)-(52), transcribed from the text-extracted seed
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class PrintedEntry:
    """One entry of a printed equation: the extracted text, the readings it admits (SymPy syntax in
    the names of :func:`printed_symbols`; several when the extraction is ambiguous, none when it is
    illegible) and the fixes applied.

    Parameters
    ----------
    equation : str
        The equation number (``"22"``).
    entry : str
        Which entry (``"A_x"``, ``"Omega_y"``, ``"wdot_z"``).
    raw : str
        The extracted text as printed.
    readings : tuple of str
        The readings it admits, in SymPy syntax.
    fixes : str
        The repairs of extraction damage applied.
    """

    equation: str
    entry: str
    raw: str
    readings: tuple[str, ...]
    fixes: str = ""

    @property
    def legible(self) -> bool:
        """True when the entry admits at least one reading."""
        return bool(self.readings)


def printed_symbols() -> dict[str, sp.Symbol]:
    """Names used in the transcriptions: m1, Ixx1, Iyy1, Izz1, a1, b1, c1, wx1, wy1, wz1 (and ...2).

    Returns
    -------
    dict of str to sympy.Symbol
        The symbols by name (positive where the quantity is).
    """
    out = {}
    for j, ps in ((1, P1), (2, P2)):
        out.update({f"m{j}": ps.m, f"Ixx{j}": ps.Ixx, f"Iyy{j}": ps.Iyy, f"Izz{j}": ps.Izz})
        out.update({f"{n}{j}": s for n, s in zip("abc", ps.half_lengths)})
        out.update({f"w{c}{j}": s for c, s in zip("xyz", ps.w)})
    return out


def parse_reading(text: str) -> sp.Expr:
    """One reading of a printed entry as a SymPy expression in :func:`printed_symbols`.

    Parameters
    ----------
    text : str
        The reading, in SymPy syntax.

    Returns
    -------
    sympy.Expr
        The parsed expression.
    """
    return sp.sympify(text, locals=printed_symbols())


_MU = "1/m1 + 1/m2"
_Z_OR_X1 = ("Izz1", "Ixx1")


def _alts(template: str, **choices) -> tuple[str, ...]:
    """All readings of ``template`` with each ``{name}`` replaced by each of its alternatives."""
    out = [template]
    for name, options in choices.items():
        out = [t.replace("{" + name + "}", o) for t in out for o in options]
    return tuple(out)


PRINTED: tuple[PrintedEntry, ...] = (
    # ---- Eq (22), Figure 2(A) ----
    PrintedEntry("22", "A_x", r"\frac{a_{2}^{2}}{I_{yy2}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"a2**2/Iyy2 + {_MU}",), "row printed without its two zero entries (layout)"),
    PrintedEntry("22", "A_y", r"0 & \frac{a_{1}^{2}}{I_{zz1}} + \frac{a_{2}^{2}}{I_{zz2}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"a1**2/Izz1 + a2**2/Izz2 + {_MU}",), "trailing zero missing (layout)"),
    PrintedEntry("22", "A_z", r"0 & 0 & \frac{a_{1}^{2}}{I_{yy1}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"a1**2/Iyy1 + {_MU}",)),
    PrintedEntry("22", "Omega_x",
                 r"a_{1}(\omega_{y1}^{2} + \omega_{z1}^{2}) + \frac{a_{2}\omega_{x2}\omega_{z2}(I_{zz2} - I_{xx2} - I_{yy2})}{I_{yy2}}",
                 ("a1*(wy1**2 + wz1**2) + a2*wx2*wz2*(Izz2 - Ixx2 - Iyy2)/Iyy2",)),
    PrintedEntry("22", "Omega_y",
                 r"\frac{a_{1}\omega_{x1}\omega_{y1}(I_{yy1} - I_{zz1} - I_{xx1})}{I_{zz1}} + \frac{a_{2}\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2} - I_{xx2})}{I_{zy2}}",
                 _alts("a1*wx1*wy1*(Iyy1 - Izz1 - Ixx1)/Izz1 + a2*wy2*wz2*(Iyy2 - Izz2 - Ixx2)/{d}", d=("Izz2", "Iyy2")),
                 "I_{zy2} (a product of inertia, zero by assumption 2) read as I_zz2 or I_yy2"),
    PrintedEntry("22", "Omega_z",
                 r"\frac{a_{2}\omega_{x2}\omega_{x2}(I_{y2} - I_{xx2} - I_{xx2})}{I_{zz1}} + \frac{a_{2}\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2} - I_{xx2})}{I_{zy1}}",
                 (), "illegible: particle-2 velocities over particle-1 moments, repeated subscripts, second term copies Omega_y"),
    # ---- Eq (23), Figure 2(B) ----
    PrintedEntry("23", "A_x", r"\frac{c_{1}^{2}}{I_{yy1}} + \frac{a_{2}^{2}}{I_{yy2}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"c1**2/Iyy1 + a2**2/Iyy2 + {_MU}",)),
    PrintedEntry("23", "A_y", r"\frac{c_{1}^{2}}{I_{zx1}} + \frac{a_{2}^{2}}{I_{zz2}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 _alts(f"c1**2/{{z}} + a2**2/Izz2 + {_MU}", z=("Ixx1", "Izz1")),
                 "I_{zx1} (a product of inertia) read as I_xx1 or I_zz1"),
    PrintedEntry("23", "A_z", r"\frac{1}{m_{1}} + \frac{1}{m_{2}}", (_MU,)),
    PrintedEntry("23", "Omega_x",
                 r"\frac{c_{1}\omega_{x1}\omega_{z1}(I_{xx1} - I_{yy1} - I_{zx1})}{I_{yy1}} + \frac{a_{2}\omega_{x2}\omega_{z2}(I_{zz2} - I_{xx2} - I_{yy2})}{I_{zy2}}",
                 _alts("c1*wx1*wz1*(Ixx1 - Iyy1 - {z})/Iyy1 + a2*wx2*wz2*(Izz2 - Ixx2 - Iyy2)/{d}", z=_Z_OR_X1, d=("Izz2", "Iyy2")),
                 "I_{zx1} read as I_zz1 or I_xx1; I_{zy2} read as I_zz2 or I_yy2"),
    PrintedEntry("23", "Omega_y",
                 r"\frac{c_{1}\omega_{y1}\omega_{z1}(I_{yy1} - I_{zx1})}{I_{xx1}} + \frac{a_{2}\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2} - I_{xx2})}{I_{zz2}}",
                 _alts("c1*wy1*wz1*(Iyy1 - {z})/Ixx1 + a2*wy2*wz2*(Iyy2 - Izz2 - Ixx2)/Izz2", z=_Z_OR_X1),
                 "I_{zx1} read as I_zz1 or I_xx1"),
    PrintedEntry("23", "Omega_z", "(row missing from the extraction)", (), "illegible: the extracted vector has two rows"),
    # ---- Eq (24), Figure 2(C) ----
    PrintedEntry("24", "A_x", r"\frac{a_{2}^{2}}{I_{xx2}} + \frac{c_{1}^{2}}{I_{yy1}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"a2**2/Ixx2 + c1**2/Iyy1 + {_MU}",)),
    PrintedEntry("24", "A_y", r"\frac{c_{1}^{2}}{I_{xx1}} + \frac{a_{2}^{2}}{I_{z22}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"c1**2/Ixx1 + a2**2/Izz2 + {_MU}",), "I_{z22} read as I_zz2 (digit 2 for the letter z)"),
    PrintedEntry("24", "A_z",
                 r"0 & 0 & \frac{c_{1}^{2}}{I_{xx1}} + \frac{a_{2}^{2}}{I_{x22}} + \frac{1}{m_{1}} + \frac{1}{m_{2}} & 0 \\ 0 & 0 & \frac{1}{m_{1}} + \frac{1}{m_{2}} & 0 \\ \dots",
                 (_MU, f"c1**2/Ixx1 + a2**2/Ixx2 + {_MU}"),
                 "the matrix is extracted with five rows; its last diagonal entry is read as 1/m1 + 1/m2 "
                 "(or, from the third row, c1^2/I_xx1 + a2^2/I_xx2 + 1/m1 + 1/m2 with I_{x22} as I_xx2)"),
    PrintedEntry("24", "Omega_x",
                 r"\frac{c_{1}\omega_{x1}\omega_{z1}(I_{xx1} - I_{yy1} - I_{zx1})}{I_{xx1}} + \frac{a_{2}\omega_{x2}\omega_{z2}(I_{zz2} - I_{xx2} - I_{yy2})}{I_{xx2}}",
                 _alts("c1*wx1*wz1*(Ixx1 - Iyy1 - {z})/Ixx1 + a2*wx2*wz2*(Izz2 - Ixx2 - Iyy2)/Ixx2", z=_Z_OR_X1),
                 "I_{zx1} read as I_zz1 or I_xx1"),
    PrintedEntry("24", "Omega_y",
                 r"\frac{c_{1}\omega_{y1}\omega_{z1}(I_{yy1} - I_{zz1})}{I_{xx1}} + \frac{a_{2}\omega_{x2}\omega_{z2}(I_{zx2} - I_{yy2} - I_{zz2})}{I_{zz2}}",
                 _alts("c1*wy1*wz1*(Iyy1 - Izz1)/Ixx1 + a2*wx2*wz2*({z} - Iyy2 - Izz2)/Izz2", z=("Izz2", "Ixx2")),
                 "I_{zx2} read as I_zz2 or I_xx2"),
    PrintedEntry("24", "Omega_z",
                 r"\frac{c_{1}\omega_{y1}\omega_{z1}(I_{yy1} - I_{zz1} - I_{xx1})}{I_{xx1}} + \frac{a_{2}\omega_{x2}\omega_{z2}(I_{xz2} - I_{xx2} - I_{yy2})}{I_{zz2}}",
                 _alts("c1*wy1*wz1*(Iyy1 - Izz1 - Ixx1)/Ixx1 + a2*wx2*wz2*({z} - Ixx2 - Iyy2)/Izz2", z=("Ixx2", "Izz2")),
                 "I_{xz2} read as I_xx2 or I_zz2"),
    # ---- Eq (50), Figure 2(A) ----
    PrintedEntry("50", "wdot_x",
                 r"-\frac{\omega_{yl}\omega_{z1}(I_{yy1} - I_{zz1})}{I_{xx1}} - \frac{\omega_{x2}\omega_{y2}(I_{xx2} - I_{yy2})}{I_{zz2}}",
                 ("-wy1*wz1*(Iyy1 - Izz1)/Ixx1 - wx2*wy2*(Ixx2 - Iyy2)/Izz2",), r"\omega_{yl} read as omega_y1 (letter l for digit 1)"),
    PrintedEntry("50", "wdot_y",
                 r"\frac{\omega_{x1}\omega_{z1}(I_{xx1} - I_{zz1})}{I_{yy1}} + \frac{\omega_{x2}\omega_{z2}(I_{xx2} - I_{zz2})}{I_{yy2}}",
                 ("wx1*wz1*(Ixx1 - Izz1)/Iyy1 + wx2*wz2*(Ixx2 - Izz2)/Iyy2",)),
    PrintedEntry("50", "wdot_z",
                 r"-\frac{\omega_{x1}\omega_{y1}(I_{xx1} - I_{yy1})}{I_{zz1}} - \frac{\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2})}{I_{xx2}}",
                 ("-wx1*wy1*(Ixx1 - Iyy1)/Izz1 - wy2*wz2*(Iyy2 - Izz2)/Ixx2",)),
    # ---- Eq (51), Figure 2(B): extracted twice; both renderings are readings ----
    PrintedEntry("51", "wdot_x",
                 r"(1) -\frac{\omega_{yl}\omega_{z1}(I_{yy1} - I_{zz1})}{I_{zz1}} - \frac{\omega_{x2}\omega_{y2}(I_{xx2} - I_{yy2})}{I_{zz2}};  "
                 r"(2) -\frac{\omega_{yl}\omega_{z1}(l_{yy1} - l_{zz1})}{I_{zx1}} - \frac{\omega_{x2}\omega_{y2}(l_{xx2} - l_{yy2})}{I_{zz2}}",
                 ("-wy1*wz1*(Iyy1 - Izz1)/Izz1 - wx2*wy2*(Ixx2 - Iyy2)/Izz2",
                  *_alts("-wy1*wz1*(Iyy1 - Izz1)/{z} - wx2*wy2*(Ixx2 - Iyy2)/Izz2", z=_Z_OR_X1)),
                 r"two renderings; \omega_{yl} as omega_y1, l as I, I_{zx1} read as I_zz1 or I_xx1"),
    PrintedEntry("51", "wdot_y",
                 r"(1) -\frac{\omega_{x1}\omega_{z1}(I_{xx1} - I_{zz1})}{I_{yy1}} + \frac{\omega_{x2}\omega_{x2}(I_{xx2} - I_{zz2})}{I_{xx2}};  "
                 r"(2) \frac{\omega_{x1}\omega_{z1}(l_{xx1} - l_{zz1})}{I_{yy1}} + \frac{\omega_{x2}\omega_{z2}(l_{xx2} - l_{zz2})}{I_{yy2}}",
                 ("-wx1*wz1*(Ixx1 - Izz1)/Iyy1 + wx2*wx2*(Ixx2 - Izz2)/Ixx2",
                  "wx1*wz1*(Ixx1 - Izz1)/Iyy1 + wx2*wz2*(Ixx2 - Izz2)/Iyy2"),
                 "two renderings; l as I"),
    PrintedEntry("51", "wdot_z",
                 r"(1) -\frac{\omega_{x1}\omega_{y1}(I_{xx1} - I_{yy1})}{I_{zz1}} - \frac{\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2})}{I_{xx2}};  "
                 r"(2) -\frac{\omega_{xl}\omega_{y1}(l_{xx1} - l_{yy1})}{I_{zx1}} - \frac{\omega_{y2}\omega_{z2}(l_{yy2} - l_{zz2})}{I_{zz2}}",
                 ("-wx1*wy1*(Ixx1 - Iyy1)/Izz1 - wy2*wz2*(Iyy2 - Izz2)/Ixx2",
                  *_alts("-wx1*wy1*(Ixx1 - Iyy1)/{z} - wy2*wz2*(Iyy2 - Izz2)/Izz2", z=_Z_OR_X1)),
                 r"two renderings; \omega_{xl} as omega_x1, l as I, I_{zx1} read as I_zz1 or I_xx1"),
    # ---- Eq (52), Figure 2(C): extracted twice ----
    PrintedEntry("52", "wdot_x",
                 r"(1) -\frac{\omega_{yl}\omega_{z1}(I_{yy1} - I_{zz1})}{I_{zz1}} + \frac{\omega_{x2}\omega_{y2}(I_{xx2} - I_{yy2})}{I_{xx2}};  "
                 r"(2) -\frac{\omega_{yl}\omega_{z1}(I_{yy1} - I_{zz1})}{I_{xx1}} + \frac{\omega_{x2}\omega_{y2}(I_{xx2} - I_{yy2})}{I_{zz2}}",
                 ("-wy1*wz1*(Iyy1 - Izz1)/Izz1 + wx2*wy2*(Ixx2 - Iyy2)/Ixx2",
                  "-wy1*wz1*(Iyy1 - Izz1)/Ixx1 + wx2*wy2*(Ixx2 - Iyy2)/Izz2"),
                 r"two renderings; \omega_{yl} as omega_y1"),
    PrintedEntry("52", "wdot_y",
                 r"(1) -\frac{\omega_{x1}\omega_{y1}(I_{yy1} - I_{zz1})}{I_{yy1}} + \frac{\omega_{x2}\omega_{y2}(I_{yy2} - I_{zz2})}{I_{xx2}};  "
                 r"(2) \frac{\omega_{x1}\omega_{z1}(I_{xx1} - I_{zz1})}{I_{yy1}} + \frac{\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2})}{I_{xx2}}",
                 ("-wx1*wy1*(Iyy1 - Izz1)/Iyy1 + wx2*wy2*(Iyy2 - Izz2)/Ixx2",
                  "wx1*wz1*(Ixx1 - Izz1)/Iyy1 + wy2*wz2*(Iyy2 - Izz2)/Ixx2"),
                 "two renderings"),
    PrintedEntry("52", "wdot_z",
                 r"(1) -\frac{\omega_{x1}\omega_{y1}(I_{xx1} - I_{yy1})}{I_{xy1}} - \frac{\omega_{x2}\omega_{z2}(I_{yy2} - I_{zz2})}{I_{xy2}};  "
                 r"(2) -\frac{\omega_{x1}\omega_{y1}(I_{xx1} - I_{yy1})}{I_{zz1}} - \frac{\omega_{x2}\omega_{z2}(I_{xx2} - I_{zz2})}{I_{yy2}}",
                 (*_alts("-wx1*wy1*(Ixx1 - Iyy1)/{d1} - wx2*wz2*(Iyy2 - Izz2)/{d2}", d1=("Ixx1", "Iyy1"), d2=("Ixx2", "Iyy2")),
                  "-wx1*wy1*(Ixx1 - Iyy1)/Izz1 - wx2*wz2*(Ixx2 - Izz2)/Iyy2"),
                 "two renderings; in (1) the products of inertia I_{xy1}, I_{xy2} read as I_xx or I_yy"),
)

PANELS = {"A": ("22", "50"), "B": ("23", "51"), "C": ("24", "52")}
ENTRY_INDEX = {"A_x": ("A", 0), "A_y": ("A", 1), "A_z": ("A", 2), "Omega_x": ("Omega", 0), "Omega_y": ("Omega", 1),
               "Omega_z": ("Omega", 2), "wdot_x": ("wdot_c", 0), "wdot_y": ("wdot_c", 1), "wdot_z": ("wdot_c", 2)}


def printed_entries(equation: str) -> list[PrintedEntry]:
    """The transcribed entries of one printed equation.

    Parameters
    ----------
    equation : str
        The equation number (``"22"``).

    Returns
    -------
    list of PrintedEntry
        Its entries, in printed order.
    """
    return [e for e in PRINTED if e.equation == equation]


def derived_entry(derived: dict[str, sp.Matrix], entry: str) -> sp.Expr:
    """The derived value of a printed entry: a diagonal entry of ``A`` or a component of ``Omega`` or ``wdot_c``.

    Parameters
    ----------
    derived : dict of str to sympy.Matrix
        ``{"A": ..., "Omega": ..., "wdot_c": ...}`` from the general kinematics.
    entry : str
        The entry name (``"A_x"``, ``"Omega_y"``, ``"wdot_z"``).

    Returns
    -------
    sympy.Expr
        The derived entry.
    """
    part, i = ENTRY_INDEX[entry]
    M = derived[part]
    return M[i, i] if part == "A" else M[i]


def compare_entry(derived: sp.Expr, e: PrintedEntry, substitutions: dict | None = None) -> int | None:
    """Index of the first reading identical to ``derived`` (SymPy, exact), -1 if none, None if illegible.

    Parameters
    ----------
    derived : sympy.Expr
        The derived entry (:func:`derived_entry`).
    e : PrintedEntry
        The printed entry.
    substitutions : dict, optional
        Substitutions applied to each reading before comparing.

    Returns
    -------
    int or None
        The index of the matching reading.
    """
    if not e.legible:
        return None
    for k, text in enumerate(e.readings):
        printed = parse_reading(text).subs(substitutions or {})
        if sp.simplify(sp.cancel(derived - printed)) == 0:
            return k
    return -1
