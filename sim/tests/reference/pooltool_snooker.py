"""Snooker shots for the snooker table's reference tests (sim/tests/cli.rs), simulated by
pooltool 0.6.0 on its snooker table with its snooker balls and its default resolver
(cushions `stronge_compliant`).

    pip install --no-deps pooltool-billiards==0.6.0   # then its requirements, see its README
    HOME=$(mktemp -d) python pooltool_snooker.py sim/tests/reference

pooltool's snooker table (1.7465 x 3.5445 m) is a little smaller than breakshot's (1.778 x
3.569 m), with its own pockets; both have the cushion noses at x = 0 and y = 0. So every
shot here stays in the bottom-left part of the table until its last compared sample (the
script checks it): the cushions it meets are the two at x = 0 and y = 0, away from any
pocket, and the scene gives pooltool's balls and cloth as its physics. Each shot is written
as NAME.scene.json (a breakshot scene) and NAME.expected.json (the cushion contacts, the
position at a few times, the rest).
"""

import math
import os
import sys

import pooltool as pt

# The same evolution, scene physics, set-off and files as the pool tables' cushion shots.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pooltool_cushions import physics, set_off, state_at, write  # noqa: E402

# Far enough from breakshot's larger table's right and top cushions and from both tables' pockets.
REGION = 1.4


def shot(out, name, pos, angle_deg, times, *, stick=None, vel_spin=None):
    """A single cue ball on pooltool's snooker table, struck by the cue (stick = (V0, a, b))
    or already moving (vel_spin = (speed, spin)); compared at `times` (s)."""
    table = pt.Table.default(pt.TableType.SNOOKER)
    params = pt.BallParams.default(game_type=pt.GameType.SNOOKER)
    ball = pt.Ball.create("cue", xy=pos, **{
        k: getattr(params, k) for k in ["m", "R", "u_s", "u_r", "u_b", "e_b", "e_c", "f_c", "g"]
    })
    ball.params = params
    system = pt.System(table=table, balls={"cue": ball}, cue=pt.Cue(cue_ball_id="cue"))
    scene = {"table": "snooker", "physics": physics(ball, table),
             "models": {"cushion": "stronge"}}
    set_off(system, ball, scene, pos, angle_deg, stick, vel_spin)
    pt.simulate(system, inplace=True)
    cue = system.balls["cue"]
    last = times[-1]
    for s in cue.history.states:
        if s.t <= last:
            x, y = s.rvw[0][:2]
            assert 0 < x < REGION and 0 < y < REGION, f"{name} leaves the region at {s.t} s"
    cushions = [
        {"t": e.time, "cushion": e.ids[1]}
        for e in system.events
        if "cushion" in e.event_type.name.lower() and e.time <= last
    ]
    assert cushions, f"{name} meets no cushion"
    expected = {
        "source": "pooltool 0.6.0, snooker table and balls, default resolver: "
                  "stronge_compliant cushions (omega_ratio 1.8)",
        "cushions": cushions,
        "samples": [{"t": t, "pos": list(state_at(cue, t)[0][:2])} for t in times],
    }
    if system.t <= last:
        expected["balls"] = {"cue": {"pos": list(cue.state.rvw[0][:2]), "rest_time": system.t}}
    write(out, name, scene, expected)


def main(out):
    # Into the left cushion at 20 degrees off square: a centre-ball strike, and one with
    # draw and side.
    shot(out, "snooker_cushion_20_strike", (0.9, 0.9), 200.0, [0.25, 0.5, 0.75, 1.0],
         stick=(1.5, 0.0, 0.0))
    shot(out, "snooker_cushion_20_draw_side", (0.9, 0.9), 200.0, [0.25, 0.5, 0.75, 1.0],
         stick=(1.5, 0.3, -0.3))
    # Sliding without spin nearly square into the bottom cushion, slow enough to come to
    # rest inside the region: the slide, the roll, the cushion and the rest.
    shot(out, "snooker_cushion_stun_to_rest", (0.8, 0.5), 265.0, [0.5, 1.0, 2.0, 4.0],
         vel_spin=(0.9, [0.0, 0.0, 0.0]))
    # Rolling with side spin at 40 degrees into the left cushion.
    v = 1.0
    R = pt.BallParams.default(game_type=pt.GameType.SNOOKER).R
    d = (math.cos(math.radians(220)), math.sin(math.radians(220)))
    shot(out, "snooker_cushion_40_roll_side", (0.7, 1.1), 220.0, [0.5, 1.0, 1.5],
         vel_spin=(v, [-v / R * d[1], v / R * d[0], 20.0]))


if __name__ == "__main__":
    main(sys.argv[1])
