"""What an effect costs: relacc's forward dynamics, Pinocchio and MuJoCo with no effect, each one, and all.

An effect that is off is not computed at all (relacc: no term is assembled;
MuJoCo: the gravity, spring and damper flags are off; Pinocchio: no
generalized force is formed), so the no-effect rows are the cheapest.

Run:  python benchmarks/effects.py [--states N]
"""

import argparse
import sys

import relacc
from relacc import dynamics
from relacc.core.states import random_states
from relacc.dynamics.effects import NONE, Effects
from relacc.engines import load_engine
from relacc.fixtures import load
from relacc.tradeoff.throughput import wall_times

ALL = Effects(gravity=[0, 0, -9.81], spring_stiffness=50.0, spring_damping=0.5, ball_damping=0.02,
              force_G2=[1.0, 0.0, 0.0], torque_B1=[0.0, 0.0, 0.1], torque_B2=[0.1, 0.0, 0.0])


def per_state(fn, n, repeats=7):
    """Microseconds per state: median of ``repeats`` calls over ``n`` states."""
    return wall_times(fn, repeats, warmups=1)[0] / n * 1e6


def main(argv=None):
    parser = argparse.ArgumentParser(description="cost of the effects, per state")
    parser.add_argument("--states", type=int, default=20_000)
    args = parser.parse_args(argv)
    fixture = load()
    chain = fixture.chain
    s = random_states(2, args.states, 0)
    mj, pn = load_engine("mujoco", fixture), load_engine("pinocchio", fixture)
    x = mj.engine_input("quaternion", relacc.Case(2), s.q, s.u, None)
    xp = pn.engine_input("quaternion", relacc.Case(2), s.q, s.u, None)
    rows = [("none", NONE)] + [(name, ALL.without_all_but(name)) for name in ALL.active()] + [("all", ALL)]
    print(f"microseconds per state ({args.states} states, case 2); relacc: dynamics.accelerations (compiled); "
          "Pinocchio: aba with the effects' forces; MuJoCo: mj_forward")
    print(f"{'effects':18s} {'relacc':>8s} {'pinocchio':>10s} {'mujoco':>8s}")
    for name, eff in rows:
        r = per_state(lambda: dynamics.accelerations(chain, 2, s.q, s.u, eff), args.states)
        p = per_state(lambda: pn.forward_dynamics(xp.q, xp.v, eff), args.states, repeats=3)
        m = per_state(lambda: mj.forward_dynamics(x.q, x.v, eff), args.states, repeats=3)
        print(f"{name:18s} {r:8.3f} {p:10.3f} {m:8.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
