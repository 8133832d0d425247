"""``relacc compare``: one model file in MuJoCo, Pinocchio and Drake; the audit and the dynamics, as text or JSON."""

from __future__ import annotations

import json

from relacc.core.tolerances import EPS


def cmd_compare(args) -> int:
    from relacc.validation.robots import compare

    out = None
    if args.out:
        from relacc import files

        out = files.check_output_file(args.out)  # before the work: a bad path is a one-line error up front
    result = compare(args.model, urdf=args.urdf, engines=args.engines, n_states=args.states, seed=args.seed)
    if out is not None:
        from relacc.report.robot import write

        write(result, out)
    if args.json:
        print(json.dumps(result.as_json(), indent=2))
    else:
        print(text(result) + (f"\nwrote {out}" if out is not None else ""))
    return result.exit_code


def text(result) -> str:
    """The comparison as lines of text: engines, audit rows with causes, dynamics per quantity and engine."""
    data = result.as_json()
    lines = [f"relacc compare {data['model']}" + (f" (Pinocchio: {data['urdf']})" if data["urdf"] else "")
             + f"; {data['states']} random states and the reference configuration, seed {data['seed']}",
             "engines (MuJoCo is the reference; coordinates: MuJoCo's, through each engine's speed map):"]
    for name, e in data["engines"].items():
        status = f"nq {e['nq']}, nv {e['nv']}" if e["loaded"] else f"not loaded: {e['error']}"
        n = len(e["warnings"])
        warned = f"; {n} parser warning{'s' if n != 1 else ''} (in --json)" if n else ""
        lines.append(f"  {name:9s} {status}{warned}")
    lines.append(f"audit: {len(data['audit'])} difference{'s' if len(data['audit']) != 1 else ''}")
    for a in data["audit"]:
        values = ", ".join(f"{k} {_short(v)}" for k, v in a.items() if k not in ("item", "where", "cause"))
        lines.append(f"  {a['item']}: {a['where']}: {values}")
        lines.append(f"    cause: {a['cause']}")
    lines.append("dynamics (normalized error at the worst state; tolerance c eps per link):")
    for quantity, row in data["dynamics"].items():
        for engine, r in row["engines"].items():
            verdict = "agree" if r["ok"] else "DIFFER"
            lines.append(f"  {quantity:22s} {engine:9s} {r['max_error']:9.3g} ({r['max_error'] / EPS:.3g} eps; "
                         f"tolerance {r['tolerance']:.3g})  {verdict}" + (f": {r['cause']}" if r["cause"] else ""))
    lines.append("every engine sees the same robot and the dynamics agree" if data["agree"] else
                 "the engines DISAGREE (exit 1)")
    return "\n".join(lines)


def _short(value) -> str:
    if isinstance(value, list):
        return "[" + ", ".join(_short(v) for v in value) + "]"
    return f"{value:.6g}" if isinstance(value, float) else str(value)
