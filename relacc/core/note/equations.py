"""Registry of the note's formulas: one entry per equation id.

Each entry says which case it belongs to, which output of
:func:`relacc.g2_kinematics` it is measured through (the errata compare that
output, computed with only this id's printed form, against the engines),
how the note presents it (``kind``), the printed and the corrected formula in
LaTeX, and a one-line explanation.

``kind`` is one of

* ``"printed"``: the note prints a formula; the errata decide ``ok`` or ``wrong``.
* ``"ambiguous"``: the printed symbols admit readings of which only one is
  right; the printed variant implements the literal reading.
* ``"missing"``: announced but not printed; only the derived form exists.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Equation:
    """One formula of the note.

    Attributes:
        id: equation id (``eq1`` ... ``eq12``, ``case1-a``, ``case2-a.1`` ...).
        case: 1, 2 or 3.
        quantity: output it is measured through: ``velocity``, ``V``, ``Vdot``
            or ``acceleration`` (all of G2, fixed components).
        kind: ``printed``, ``ambiguous`` or ``missing``.
        title: what the formula gives, in words.
        printed: the formula as the note prints it (LaTeX), or None if missing.
        corrected: the formula relacc uses by default (LaTeX), or None when
            it is the printed one.
        explanation: one line; for ok formulas, how the symbols are read.
        differs: True when the printed variant is a different computation.
    """

    id: str
    case: int
    quantity: str
    kind: str
    title: str
    printed: str | None
    corrected: str | None
    explanation: str
    differs: bool = False


EQUATIONS: tuple[Equation, ...] = (
    Equation(
        "eq1", 1, "velocity", "printed", "velocity of G2, Case 1 speeds",
        r"\{v_{G_2}\} = \{\dot s_1\} - ([\tilde q_2]+[\tilde s_2]+[\tilde r_2])\{\omega_{B_1}\}"
        r" + [R_{B_1}]^T\{\dot s_2'\} - [\tilde r_2][R_{B_1}]^T\{\hat\omega_{B_2}\}",
        None,
        "Right as printed.",
    ),
    Equation(
        "eq2", 2, "velocity", "printed", "velocity of G2, Case 2 speeds",
        r"\{v_{G_2}\} = \{\dot s_1\} - [R_{B_1}]^T([\tilde q_2']+[\tilde s_2'])\{\omega_{B_1}'\}"
        r" - [R_{B_2}]^T[\tilde r_2'][{}^{B_2}R_{B_1}]^T\{\omega_{B_1}'\} + [R_{B_1}]^T\{\dot s_2'\}"
        r" - [R_{B_2}]^T[\tilde r_2']\{\hat\omega_{B_2}'\}",
        None,
        "Right as printed, with [^{B2}R_{B1}] mapping B2 to B1 components.",
    ),
    Equation(
        "eq3", 1, "V", "printed", "partial velocity matrices, Case 1",
        r"[v_{G_2,\omega_{B_1}}] = -([\tilde q_2]+[\tilde s_2]+[\tilde r_2]),\;"
        r"[v_{G_2,\dot s_2'}] = [R_{B_1}]^T,\; [v_{G_2,\dot\omega_{B_2}}] = -[\tilde r_2][R_{B_1}]^T",
        r"[v_{G_2,\hat\omega_{B_2}}] = -[\tilde r_2][R_{B_1}]^T",
        "Right; the subscript printed as omega-dot_B2 is the speed omega-hat_B2 (typesetting only).",
    ),
    Equation(
        "eq4", 1, "acceleration", "ambiguous", "acceleration of G2, Case 1",
        r"\ldots + [v_{G_2,\dot\omega_{B_2}}]\{\dot{\hat\omega}_{B_2}\}"
        r" + [\dot v_{G_2,\dot\omega_{B_2}}]\{\dot\omega_{B_2}\}",
        r"\ldots + [v_{G_2,\hat\omega_{B_2}}]\{\dot{\hat\omega}_{B_2}\}"
        r" + [\dot v_{G_2,\hat\omega_{B_2}}]\{\hat\omega_{B_2}\}",
        "The last factor is printed omega-dot_B2; read literally (B2's angular acceleration) it is "
        "wrong, read as the subscripts read that glyph (omega-hat_B2) it is the chain rule of eq3.",
        differs=True,
    ),
    Equation(
        "case1-a", 1, "Vdot", "printed", "derivative of the omega_B1 block, Case 1 (a)",
        r"[\dot v_{G_2,\omega_{B_1}}] = -([\dot{\tilde q}_2]+[\dot{\tilde s}_2]+[\dot{\tilde r}_2])",
        None,
        "Right as printed (unnumbered part a of Case 1).",
    ),
    Equation(
        "eq5", 1, "Vdot", "printed", "rate of q2 (fixed components)",
        r"\{\dot q_2\} = [\tilde\omega_{B_1}][R_{B_1}]^T\{q_2'\}",
        None,
        "Right as printed.",
    ),
    Equation(
        "eq6", 1, "Vdot", "printed", "rate of s2 (fixed components)",
        r"\{\dot s_2\} = [\tilde\omega_{B_1}][R_{B_1}]^T\{s_2'\} + [R_{B_1}]^T\{\dot s_2'\}",
        None,
        "Right as printed.",
    ),
    Equation(
        "eq7", 1, "Vdot", "printed", "rate of r2 (fixed components)",
        r"\{\dot r_2\} = [\tilde\omega_{B_2}][R_{B_2}]^T\{r_2'\}",
        r"\omega_{B_2} = \omega_{B_1} + [R_{B_1}]^T\hat\omega_{B_2}",
        "Right, reading the undefined omega_B2 as B2's angular velocity in R (fixed components).",
    ),
    Equation(
        "eq8", 1, "Vdot", "printed", "derivative of the s2' block, Case 1 (b)",
        r"[\dot v_{G_2,\dot s_2'}] = [\dot R_{B_1}]^T = [\tilde\omega_{B_1}][R_{B_1}]^T",
        None,
        "Right as printed.",
    ),
    Equation(
        "eq9.1", 1, "Vdot", "printed", "derivative of the omega-hat_B2 block, Case 1 (c), first form",
        r"[\dot v_{G_2,\hat\omega_{B_2}}] = -[\dot{\tilde r}_2][R_{B_1}]^T - [\tilde r_2][\dot R_{B_1}]^T",
        None,
        "Right as printed (with [R_B1-dot]^T from eq8).",
    ),
    Equation(
        "eq9.2", 1, "Vdot", "printed", "derivative of the omega-hat_B2 block, Case 1 (c), final form",
        r"[\dot v_{G_2,\hat\omega_{B_2}}] = -[\dot{\tilde r}_2][R_{B_1}]^T - [\tilde r_2][\tilde\omega_{B_1}]^T",
        r"[\dot v_{G_2,\hat\omega_{B_2}}] = -[\dot{\tilde r}_2][R_{B_1}]^T"
        r" - [\tilde r_2][\tilde\omega_{B_1}][R_{B_1}]^T",
        "Wrong: [R_B1-dot]^T = [omega_B1~][R_B1]^T was printed as [omega_B1~]^T, dropping [R_B1]^T "
        "and transposing the skew matrix.",
        differs=True,
    ),
    Equation(
        "eq10", 2, "V", "printed", "partial velocity matrices, Case 2",
        r"[v_{G_2,\omega_{B_1}'}] = -[R_{B_1}]^T([\tilde q_2']+[\tilde s_2'])"
        r" - [R_{B_2}]^T[\tilde r_2'][{}^{B_2}R_{B_1}]^T,\; [v_{G_2,\hat\omega_{B_2}'}] = -[R_{B_2}]^T[\tilde r_2']",
        None,
        "Right as printed.",
    ),
    Equation(
        "eq11", 2, "acceleration", "missing", "acceleration of G2, Case 2",
        None,
        r"\{a_{G_2}\} = \{\ddot s_1\} + [v_{G_2,\omega_{B_1}'}]\{\dot\omega_{B_1}'\}"
        r" + [\dot v_{G_2,\omega_{B_1}'}]\{\omega_{B_1}'\} + [R_{B_1}]^T\{\ddot s_2'\}"
        r" + [\dot v_{G_2,\dot s_2'}]\{\dot s_2'\} + [v_{G_2,\hat\omega_{B_2}'}]\{\dot{\hat\omega}_{B_2}'\}"
        r" + [\dot v_{G_2,\hat\omega_{B_2}'}]\{\hat\omega_{B_2}'\}",
        "The note announces Eq. 11 but prints nothing; derived as the time derivative of eq10.",
    ),
    Equation(
        "case2-a.1", 2, "Vdot", "printed", "derivative of the omega'_B1 block, Case 2 (a), first line",
        r"[\dot v_{G_2,\omega_{B_1}'}] = -[R_{B_1}]^T[\dot{\tilde s}_2'] - [\dot R_{B_1}]^T([\tilde q_2']"
        r"+[\tilde s_2']) - [\dot R_{B_2}]^T[\tilde r_2'][{}^{B_2}R_{B_1}]^T - [R_{B_2}]^T[\tilde r_2']"
        r"[{}^{B_1}\dot R_{B_2}]",
        None,
        "Right as printed, with [^{B1}R_{B2}] = [^{B2}R_{B1}]^T and every rotation rate by the product rule.",
    ),
    Equation(
        "case2-a.2", 2, "Vdot", "printed", "derivative of the omega'_B1 block, Case 2 (a), expansion",
        r"\ldots - [R_{B_2}]^T[\tilde r_2'][\tilde\omega_{B_2}'][{}^{B_1}R_{B_2}]",
        r"\ldots + [R_{B_2}]^T[\tilde r_2'][\tilde{\hat\omega}_{B_2}'][{}^{B_1}R_{B_2}]",
        "Wrong: d/dt [^{B1}R_{B2}] = -[omega-hat'_B2~][^{B1}R_{B2}]; the expansion flips the sign and "
        "uses B2's absolute angular velocity instead of its velocity relative to B1.",
        differs=True,
    ),
    Equation(
        "case2-b", 2, "Vdot", "printed", "derivative of the s2' block, Case 2 (b)",
        r"[\dot v_{G_2,\dot s_2'}] = [\dot R_{B_1}]^T = [R_{B_1}]^T[\tilde\omega_{B_1}']",
        None,
        "Right; the subscript printed s2'-double-dot is the speed s2'-dot (typesetting only).",
    ),
    Equation(
        "case2-c", 2, "Vdot", "printed", "derivative of the omega-hat'_B2 block, Case 2 (c)",
        r"[\dot v_{G_2,\hat\omega_{B_2}'}] = -[R_{B_2}]^T[\tilde\omega_{B_2}'][\tilde r_2']",
        r"\omega_{B_2}' = [{}^{B_1}R_{B_2}]\omega_{B_1}' + \hat\omega_{B_2}'",
        "Right, reading the undefined omega'_B2 as B2's angular velocity in R (B2 components).",
    ),
    Equation(
        "case3-partials", 3, "V", "ambiguous", "velocity and partial velocity matrices, Case 3",
        r"[v_{G_2,\dot\theta_{B_2}}] = -[\tilde r_2][\omega_{B_2,\dot\theta_{B_2}}]",
        r"[v_{G_2,\dot\theta_{B_2}}] = -[\tilde r_2][R_{B_1}]^T[W_{123}(\theta_{B_2})]",
        "[omega_{B2,theta_B2-dot}] read as the 1-2-3 matrix of the previous notes (B1 components) misses "
        "[R_B1]^T; read as the partial of B2's angular velocity in fixed components it is right.",
        differs=True,
    ),
    Equation(
        "eq12", 3, "acceleration", "printed", "acceleration of G2, Case 3",
        r"\{a_{G_2}\} = \sum_k [v_{G_2,u_k}]\{\dot u_k\} + [\dot v_{G_2,u_k}]\{u_k\}",
        None,
        "Right as printed.",
    ),
    Equation(
        "case3-rates", 3, "Vdot", "ambiguous", "derivatives of the partial velocity matrices, Case 3",
        r"[\dot v_{G_2,\dot\theta_{B_2}}] = -[\dot{\tilde r}_2][\omega_{B_2,\dot\theta_{B_2}}]"
        r" - [\tilde r_2][\dot\omega_{B_2,\dot\theta_{B_2}}]",
        r"[\dot\omega_{B_2,\dot\theta_{B_2}}] = [\tilde\omega_{B_1}][R_{B_1}]^T[W_{123}]"
        r" + [R_{B_1}]^T[\dot W_{123}]",
        "Same reading as case3-partials: the derivative of [R_B1]^T W(theta_B2) has the extra "
        "term [omega_B1~][R_B1]^T W that the literal 1-2-3 derivative lacks.",
        differs=True,
    ),
)

BY_ID = {e.id: e for e in EQUATIONS}
"""Equation id -> :class:`Equation`."""

IDS = tuple(BY_ID)
"""Every equation id, in the note's order."""
