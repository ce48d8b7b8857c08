"""Cushion shots for the `stronge` model's reference tests (sim/tests/cli.rs), simulated by
pooltool 0.6.0 with its default resolver (cushions `stronge_compliant`, omega_ratio 1.8).

    pip install --no-deps pooltool-billiards==0.6.0   # then its requirements, see its README
    HOME=$(mktemp -d) python pooltool_cushions.py sim/tests/reference

HOME is a scratch folder because pooltool reads its resolver from ~/.config/pooltool: a fresh
one gives the default resolver. Each shot is written as NAME.scene.json (a breakshot scene)
and NAME.expected.json (the cushion contacts, the position at a few times, the rest).
"""

import json
import math
import os
import sys

import pooltool as pt
from pooltool.physics.evolve import evolve_ball_motion

TIMES = [0.5, 1.0, 2.0]
R = 0.028575


def state_at(ball, t):
    """The ball's position and velocity at time t, evolved from its last event before t."""
    last = [s for s in ball.history.states if s.t <= t][-1]
    p = ball.params
    rvw, _ = evolve_ball_motion(
        last.s, last.rvw, p.R, p.m, p.u_s, p.u_sp, p.u_r, p.g, t - last.t
    )
    return rvw


def physics(ball, table):
    p = ball.params
    return {
        "ball_radius": p.R, "ball_mass": p.m, "gravity": p.g, "mu_slide": p.u_s,
        "mu_roll": p.u_r, "mu_spin": p.u_sp, "e_ball": p.e_b, "e_cushion": p.e_c,
        "f_cushion": p.f_c, "cushion_height": table.cushion_segments.linear["3"].height,
    }


def set_off(system, ball, scene, pos, angle_deg, stick, vel_spin):
    """Sets the cue ball at `pos` off along `angle_deg`, struck by the cue (stick = (V0, a, b))
    or already moving (vel_spin = (speed, spin)), and gives the scene the same ball and strike."""
    if stick is not None:
        v0, a, b = stick
        system.cue.set_state(V0=v0, phi=angle_deg, a=a, b=b, theta=0.0)
        # The scene's side offset has the opposite sign of pooltool's `a`.
        scene["balls"] = [{"id": "cue", "pos": list(pos)}]
        scene["strike"] = {"ball": "cue", "speed": v0, "angle_deg": angle_deg, "tip": [-a, b]}
    else:
        speed, spin = vel_spin
        d = (math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg)))
        vel = [speed * d[0], speed * d[1]]
        ball.state.rvw[1] = [*vel, 0.0]
        ball.state.rvw[2] = spin
        ball.state.s = pt.constants.sliding
        scene["balls"] = [{"id": "cue", "pos": list(pos), "vel": vel, "spin": list(spin)}]


def write(out, name, scene, expected):
    """Writes a shot as NAME.scene.json and NAME.expected.json into `out`."""
    for suffix, data in [("scene", scene), ("expected", expected)]:
        with open(os.path.join(out, f"{name}.{suffix}.json"), "w") as f:
            json.dump(data, f, indent=1)
            f.write("\n")


def shot(out, name, pos, angle_deg, *, stick=None, vel_spin=None):
    """A single cue ball on pooltool's default 7 ft table, either struck by the cue
    (stick = (V0, a, b)) or already moving (vel_spin = (speed, spin))."""
    table = pt.Table.default()
    ball = pt.Ball.create("cue", xy=pos)
    system = pt.System(table=table, balls={"cue": ball}, cue=pt.Cue(cue_ball_id="cue"))
    scene = {"table": "7ft", "physics": physics(ball, table), "models": {"cushion": "stronge"}}
    set_off(system, ball, scene, pos, angle_deg, stick, vel_spin)
    pt.simulate(system, inplace=True)
    cue = system.balls["cue"]
    counts = {}
    for e in system.events:
        kind = e.event_type.name.lower()
        counts[kind] = counts.get(kind, 0) + 1
    expected = {
        "source": "pooltool 0.6.0, default resolver: stronge_compliant cushions (omega_ratio 1.8)",
        "event_counts": counts,
        "cushions": [
            {"t": e.time, "cushion": e.ids[1]}
            for e in system.events
            if "cushion" in e.event_type.name.lower()
        ],
        "samples": [{"t": t, "pos": list(state_at(cue, t)[0][:2])} for t in TIMES],
        "balls": {"cue": {"pos": list(cue.state.rvw[0][:2]), "rest_time": system.t}},
        "duration": system.t,
    }
    write(out, name, scene, expected)


def main(out):
    # 45° to the long rail: a sliding ball without spin, and a centre-ball strike.
    shot(out, "cushion_45_slide_7ft", (0.5, 0.3), 45.0, vel_spin=(1.5, [0.0, 0.0, 0.0]))
    shot(out, "cushion_45_strike_7ft", (0.5, 0.3), 45.0, stick=(1.5, 0.0, 0.0))
    # Rolling with side spin, and a strike with draw and side: more spin at the nose.
    v = 1.2
    d = (math.cos(math.radians(30)), math.sin(math.radians(30)))
    shot(out, "cushion_30_roll_side_7ft", (0.4, 0.3), 30.0,
         vel_spin=(v, [-v / R * d[1], v / R * d[0], 25.0]))
    shot(out, "cushion_60_strike_draw_side_7ft", (0.3, 0.25), 60.0, stick=(2.0, -0.3, -0.3))
    # Nearly square to the rail, still sliding there: the contact slides, sticks and slides
    # again (a stun ball), or sticks from the start (backspin cancels most of the slip at
    # the nose).
    shot(out, "cushion_10_stun_7ft", (0.85, 0.6), 10.0, vel_spin=(1.5, [0.0, 0.0, 0.0]))
    d = (math.cos(math.radians(3)), math.sin(math.radians(3)))
    k = 0.4 * 1.5 / R
    shot(out, "cushion_3_draw_7ft", (0.85, 0.6), 3.0,
         vel_spin=(1.5, [k * d[1], -k * d[0], 0.0]))


if __name__ == "__main__":
    main(sys.argv[1])
