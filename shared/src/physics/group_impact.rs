//! The impact of a touching group: every ball touching the colliding ones (or as near as
//! the impact closes in a microsecond) takes part, the contacts are resolved in rounds as
//! the wave a real cluster carries, and what is left is settled, so that no contact of the
//! group collides again at the same instant (see docs/physics.md, *Touching groups*).

use glam::{DVec2, DVec3};

use super::airborne;
use super::ball_ball::{self, Kinematics};
use super::ball_cushion;
use super::motion::{BallState, MotionState, Piece};
use super::params::BallBallModel;
use super::roots::{TOUCH_ACCEL, TOUCH_SPEED};
use super::shot::Ctx;
use super::table::Cushion;

/// Approach speed (m/s) under which a contact that is being pushed together (by friction
/// accelerations, not by speed) is held instead of bounced: bouncing would repeat forever
/// in ever shorter hops.
pub const HOLD_SPEED: f64 = 1e-3;
/// Gap between two balls (m) under which they count as touching: they take part in each
/// other's impacts. At the fastest legal speed the gap would close in under 1e-10 s.
pub const CONTACT_GAP: f64 = 1e-9;
/// A ball nearer to a colliding group than the group's fastest approach closes in
/// `NEAR_TIME` (s) takes part in its impact as if touching: a real impact lasts about
/// 0.2 ms (Hertzian contact), so a gap closing within a microsecond closes while the impact
/// is still going on. Resolved one pair at a time, such a gap would give a cascade.
pub const NEAR_TIME: f64 = 1e-6;
/// A pair pressed together by the cloth that meets again within `PERSIST_TIME` (s) of its
/// last impact, slower than `PERSIST_SPEED` (m/s) or than the `(1 − e)/2` of its last blow's
/// speed that a blow leaves each ball, is held rather than bounced (the persistence rule of
/// a sustained push): bounced, it would come back in ever shorter hops. A held set met
/// slower than `PERSIST_SPEED` answers as one body.
pub const PERSIST_TIME: f64 = 0.5;
/// The approach speed (m/s) of the persistence rule: see [`PERSIST_TIME`].
pub const PERSIST_SPEED: f64 = 0.05;

/// Buffers reused from one collision group to the next.
#[derive(Default)]
pub(super) struct Scratch {
    /// The balls of the touching group (ball indices, in order), those among them whose
    /// collision was predicted, and their states during the impact (indexed by slot).
    pub(super) balls: Vec<usize>,
    pub(super) seeds: Vec<usize>,
    pub(super) states: Vec<BallState>,
    /// Velocity and spin of each slot before the impact.
    pub(super) start: Vec<(DVec2, DVec3)>,
    /// By ball, the position at the impact instant of each ball of the group, written as it
    /// joins (the other entries are left from earlier impacts and never read).
    pub(super) positions: Vec<DVec2>,
    /// The group's contacts (slots `a < b`), whether each took part, and their normals.
    pub(super) contacts: Vec<(usize, usize)>,
    pub(super) acted: Vec<bool>,
    pub(super) normals: Vec<DVec2>,
    /// Cushions touching a ball of the group (slot, normal into the table, which), and
    /// whether each took part.
    pub(super) walls: Vec<(usize, DVec2, Cushion)>,
    pub(super) wall_acted: Vec<bool>,
    /// Whether each contact's pair took part in an impact less than `PERSIST_TIME` ago, and
    /// whether that impact left it held.
    pub(super) recent: Vec<bool>,
    pub(super) kept: Vec<bool>,
    /// Each contact's pair's fastest approach in its last bounce, on entry; during the
    /// impact, the fastest approach at which it is bounced now (0 if it is not).
    pub(super) blow: Vec<f64>,
    /// Contacts (indices) taking part in the current round, and which of them are resolved.
    pub(super) active: Vec<usize>,
    pub(super) done: Vec<bool>,
    /// The contacts (slots) of the connected set being resolved, and their normals.
    pub(super) component: Vec<(usize, usize)>,
    pub(super) component_normals: Vec<DVec2>,
    /// The simultaneous impact's impulses, their last change, and the velocities during the
    /// iteration.
    pub(super) lambda: Vec<f64>,
    pub(super) delta: Vec<f64>,
    pub(super) vel: Vec<DVec2>,
    /// Contacts per body in the impact, each body's mass (in balls), and each contact's
    /// bodies.
    pub(super) degree: Vec<usize>,
    pub(super) size: Vec<f64>,
    pub(super) bodies: Vec<(usize, usize)>,
    /// Slots whose state changed; each slot's acceleration after the impact; union-find
    /// parents of held contacts.
    pub(super) changed: Vec<usize>,
    pub(super) acc: Vec<DVec2>,
    pub(super) parent: Vec<usize>,
}

/// Empties `v` and fills it with `len` copies of `x`, keeping its allocation: how the
/// buffers reused from group to group, and from shot to shot, start afresh.
pub(super) fn refill<T: Clone>(v: &mut Vec<T>, len: usize, x: T) {
    v.clear();
    v.resize(len, x);
}

/// Resolves the impact of a touching group: every contact of the group (within
/// `CONTACT_GAP`, or what the impact closes in `NEAR_TIME`) takes part, whether or not its
/// own collision was predicted.
///
/// The impact runs in rounds. Each round takes every contact approaching faster than
/// `HOLD_SPEED` and resolves it from the velocities the previous round left: a contact that
/// shares no body with another by the pairwise model (restitution, throw, spin transfer), a
/// connected set of them as one simultaneous impact ([`simultaneous_impact`]). A body is a
/// ball, or a held set when the group meets slower than `PERSIST_SPEED`. A line of
/// touching balls is so resolved as the wave a real cradle carries, one contact after the
/// other, and the far ball leaves. Within a round every contact is updated from the same
/// velocities, so the result does not depend on how the balls are numbered. What the rounds
/// leave is settled ([`settle`]). Each contact that took part gives one event.
pub(super) fn group_impact(g: &mut Scratch, ctx: &Ctx) {
    refill(&mut g.acted, g.contacts.len(), false);
    refill(&mut g.wall_acted, g.walls.len(), false);
    g.normals.clear();
    for &(a, b) in &g.contacts {
        g.normals
            .push((g.states[b].pos - g.states[a].pos).normalize_or_zero());
    }
    // Slot `n` is the cushions: one body that does not move.
    g.parent.clear();
    g.parent.extend(0..=g.states.len());
    if lone_pair(g, ctx) {
        return;
    }
    // A pair pressed together by the cloth that meets again soon after its last impact is a
    // sustained push: it is settled (held), not bounced.
    if g.recent.contains(&true) {
        accelerations(g, ctx);
    }
    // Slower than a push's hop, or than what a blow leaves its pair (each ball keeps about
    // (1 − e)/2 of a blow's speed), it is the settling of that push or blow.
    let residual = (1.0 - restitution(ctx)) / 2.0;
    for k in 0..g.contacts.len() {
        let (a, b) = g.contacts[k];
        let slow = PERSIST_SPEED.max(residual * g.blow[k]);
        g.recent[k] = g.recent[k]
            && approach(g, k) < slow
            && (g.acc[a] - g.acc[b]).dot(g.normals[k]) > TOUCH_ACCEL;
        g.blow[k] = 0.0;
    }
    // A held set met slower than a push moves as one body in the rounds too: a slow meeting
    // with it is one contact, not a wave through every contact of the set. A faster blow
    // releases it, and the wave runs through it as through any touching line.
    let fastest = (0..g.contacts.len()).fold(0.0f64, |m, k| m.max(approach(g, k)));
    let bodies = fastest <= PERSIST_SPEED && join_kept(g);
    for _ in 0..rounds(g) {
        g.active.clear();
        for k in 0..g.contacts.len() {
            let u = approach(g, k);
            if u > HOLD_SPEED && !g.recent[k] {
                g.active.push(k);
                g.acted[k] = true;
                g.blow[k] = g.blow[k].max(u);
            }
        }
        let walls_approach = g
            .walls
            .iter()
            .any(|&(slot, normal, _)| -g.states[slot].vel.dot(normal) > HOLD_SPEED);
        if g.active.is_empty() && !walls_approach {
            break;
        }
        refill(&mut g.done, g.active.len(), false);
        for first in 0..g.active.len() {
            if g.done[first] {
                continue;
            }
            g.done[first] = true;
            g.component.clear();
            g.component_normals.clear();
            g.component.push(g.contacts[g.active[first]]);
            g.component_normals.push(g.normals[g.active[first]]);
            let mut k = 0;
            while k < g.component.len() {
                // Contacts sharing a body (a ball, or a held set) are one simultaneous impact.
                let (a, b) = g.component[k];
                let (a, b) = (root(&g.parent, a), root(&g.parent, b));
                for m in 0..g.active.len() {
                    let contact = g.contacts[g.active[m]];
                    let (c, d) = (root(&g.parent, contact.0), root(&g.parent, contact.1));
                    if !g.done[m] && (c == a || c == b || d == a || d == b) {
                        g.done[m] = true;
                        g.component.push(contact);
                        g.component_normals.push(g.normals[g.active[m]]);
                    }
                }
                k += 1;
            }
            let (a, b) = g.component[0];
            // A lone contact between two single balls takes the pairwise model (with throw
            // and spin transfer); one with a held set, the simultaneous impact of bodies.
            let single = |m: usize| {
                !bodies
                    || (0..g.states.len())
                        .all(|o| o == m || root(&g.parent, o) != root(&g.parent, m))
            };
            if g.component.len() == 1 && single(a) && single(b) {
                collide_pair(&mut g.states, a, b, ctx);
            } else {
                simultaneous_impact(g, restitution(ctx));
            }
        }
        // A ball driven into a cushion bounces off it, unless one of its ball contacts
        // acts in this round (then the cushion waits for the next round).
        for w in 0..g.walls.len() {
            let (slot, normal, _) = g.walls[w];
            let s = &g.states[slot];
            let busy = g.active.iter().any(|&k| {
                let (a, b) = g.contacts[k];
                a == slot || b == slot
            });
            if -s.vel.dot(normal) > HOLD_SPEED && !busy {
                let (v, w_) =
                    ball_cushion::bounce(s.vel, s.spin, normal, ctx.models.cushion, ctx.params);
                g.states[slot].vel = v;
                g.states[slot].spin = w_;
                g.wall_acted[w] = true;
            }
        }
    }
    // Nothing to settle when every contact opens faster than a push could hold it and no
    // ball touches a cushion (the common case: two balls that bounced apart).
    let open = (0..g.contacts.len()).all(|k| approach(g, k) < -HOLD_SPEED);
    if !(open && g.walls.is_empty()) {
        settle(g, ctx);
    }
}

/// The rounds of [`group_impact`] for the commonest impact: two balls and their one contact,
/// no cushion, the pair neither met of late (so no push is held) nor held. Each round then
/// resolves that contact by the pairwise model while it approaches faster than `HOLD_SPEED`,
/// as the general rounds would (no recent push, held set or other contact can apply), and
/// what is left is settled in the same way; true when it applied.
fn lone_pair(g: &mut Scratch, ctx: &Ctx) -> bool {
    if g.contacts.len() != 1 || !g.walls.is_empty() || g.recent[0] || g.kept[0] {
        return false;
    }
    let (a, b) = g.contacts[0];
    g.blow[0] = 0.0;
    for _ in 0..rounds(g) {
        let u = approach(g, 0);
        let approaching = u > HOLD_SPEED;
        if !approaching {
            break;
        }
        g.acted[0] = true;
        g.blow[0] = g.blow[0].max(u);
        collide_pair(&mut g.states, a, b, ctx);
    }
    let open = approach(g, 0) < -HOLD_SPEED;
    if !open {
        settle(g, ctx);
    }
    true
}

/// How many rounds an impact may take: enough for a wave to cross every contact and cushion
/// of the group a few times.
fn rounds(g: &Scratch) -> usize {
    4 * (g.contacts.len() + g.walls.len()) + 8
}

/// The ball–ball restitution of the collision model.
fn restitution(ctx: &Ctx) -> f64 {
    match ctx.models.ball_ball {
        BallBallModel::Ideal => 1.0,
        BallBallModel::Frictional => ctx.params.e_ball,
    }
}

/// The speed at which contact `k` of the group closes (negative: opening).
fn approach(g: &Scratch, k: usize) -> f64 {
    let (a, b) = g.contacts[k];
    (g.states[a].vel - g.states[b].vel).dot(g.normals[k])
}

/// Ends a group impact so that no contact of the group is left to collide again at the same
/// instant. A contact still approaching (slower than `HOLD_SPEED`, or after the last round)
/// takes a perfectly inelastic impact. A contact pressed together by the cloth (friction,
/// or a ball's own spin driving it on) that is not opening faster than `HOLD_SPEED` is
/// *held*: the balls it joins move on as one body, each with the group's average velocity
/// and spin, until something separates them. Without holding, the push would come back as
/// an endless stream of ever smaller bounces. Both steps keep momentum and never add energy
/// (the average minimises kinetic energy at fixed momentum).
fn settle(g: &mut Scratch, ctx: &Ctx) {
    /// Passes of inelastic impact and holding: holding can make a neighbour approach.
    const PASSES: usize = 8;
    // Held contacts stay held for the rest of the impact: balls moving as one no longer
    // press into each other, but must still share what a later pass gives one of them. A
    // contact held before that the rounds left moving as one is still held: a push on a
    // held set moves it as one body, without an event inside it.
    // Slot `n` is the cushions: one body that does not move.
    join_kept(g);
    for _ in 0..PASSES {
        // Every contact between different bodies takes part; the impact itself decides
        // which carry an impulse.
        g.component.clear();
        g.component_normals.clear();
        g.active.clear();
        let mut approaching = false;
        for k in 0..g.contacts.len() {
            let (a, b) = g.contacts[k];
            if root(&g.parent, a) != root(&g.parent, b) {
                approaching |= approach(g, k) > TOUCH_SPEED;
                g.component.push(g.contacts[k]);
                g.component_normals.push(g.normals[k]);
                g.active.push(k);
            }
        }
        let wall_body = g.states.len();
        for w in 0..g.walls.len() {
            let (slot, normal, _) = g.walls[w];
            approaching |= -g.states[slot].vel.dot(normal) > TOUCH_SPEED;
            g.component.push((wall_body, slot));
            g.component_normals.push(normal);
        }
        if approaching {
            simultaneous_impact(g, 0.0);
            for m in 0..g.component.len() {
                if g.lambda[m] > 0.0 {
                    if m < g.active.len() {
                        g.acted[g.active[m]] = true;
                    } else {
                        g.wall_acted[m - g.active.len()] = true;
                    }
                }
            }
        }
        let mut held = false;
        loop {
            held |= share_motion(g);
            if !join_pressed(g, ctx) {
                break;
            }
        }
        held |= hold_against_walls(g, ctx);
        if !approaching && !held {
            break;
        }
    }
}

/// Starts the held sets afresh (`Scratch::parent`) from the contacts held before this impact
/// whose balls still move alike; true if any set has more than one ball.
fn join_kept(g: &mut Scratch) -> bool {
    g.parent.clear();
    g.parent.extend(0..=g.states.len());
    let mut joined = false;
    for k in 0..g.contacts.len() {
        let (a, b) = g.contacts[k];
        let (sa, sb) = (&g.states[a], &g.states[b]);
        if g.kept[k] && sa.vel == sb.vel && sa.spin == sb.spin {
            let (ra, rb) = (root(&g.parent, a), root(&g.parent, b));
            g.parent[ra.max(rb)] = ra.min(rb);
            joined = true;
        }
    }
    joined
}

/// Gives every ball of each held set the set's average velocity and spin; true if that
/// changed anything.
fn share_motion(g: &mut Scratch) -> bool {
    let n = g.states.len();
    // (The cushions' body, slot n, is never joined to a ball.)
    let mut changed = false;
    for top in 0..n {
        if g.parent[top] != top {
            continue;
        }
        let (mut vel, mut spin, mut count) = (DVec2::ZERO, DVec3::ZERO, 0.0);
        for m in 0..n {
            if root(&g.parent, m) == top {
                vel += g.states[m].vel;
                spin += g.states[m].spin;
                count += 1.0;
            }
        }
        if count > 1.0 {
            let (vel, spin) = (vel / count, spin / count);
            for m in 0..n {
                let s = &mut g.states[m];
                if root(&g.parent, m) == top && (s.vel != vel || s.spin != spin) {
                    s.vel = vel;
                    s.spin = spin;
                    changed = true;
                }
            }
        }
    }
    changed
}

/// Joins the held sets of every contact pressed together by the cloth and not opening faster
/// than `HOLD_SPEED`; true if any joined.
fn join_pressed(g: &mut Scratch, ctx: &Ctx) -> bool {
    accelerations(g, ctx);
    let mut joined = false;
    for k in 0..g.contacts.len() {
        let (a, b) = g.contacts[k];
        let (ra, rb) = (root(&g.parent, a), root(&g.parent, b));
        let pressed = (g.acc[a] - g.acc[b]).dot(g.normals[k]) > TOUCH_ACCEL;
        if ra != rb && pressed && approach(g, k) > -HOLD_SPEED {
            g.parent[ra.max(rb)] = ra.min(rb);
            g.acted[k] = true;
            joined = true;
        }
    }
    joined
}

/// Records every cushion (rail or jaw) that the ball in `slot` touches.
pub(super) fn walls_touching(g: &mut Scratch, slot: usize, ctx: &Ctx) {
    let p = g.states[slot].pos;
    let reach = ctx.contact + CONTACT_GAP;
    // Every cushion lies beyond the nose lines: a ball well inside them touches none.
    let inside = ctx.table.half - DVec2::splat(reach + ctx.params.ball_radius);
    if p.x.abs() < inside.x && p.y.abs() < inside.y {
        return;
    }
    for (k, rail) in ctx.table.rails.iter().enumerate() {
        let along = rail.b - rail.a;
        let s = along.dot(p - rail.a) / along.length_squared();
        if rail.normal.dot(p - rail.a) <= reach && (0.0..=1.0).contains(&s) {
            g.walls.push((slot, rail.normal, Cushion::Rail(k as u8)));
        }
    }
    for (k, jaw) in ctx.table.jaws.iter().enumerate() {
        let d = p - jaw.center;
        if d.length() <= jaw.radius + reach {
            g.walls
                .push((slot, d.normalize_or_zero(), Cushion::Jaw(k as u8)));
        }
    }
}

/// A held set pressed into a cushion by the cloth is held by it, as a single ball is
/// ([`Simulator::bounce`]): every ball of the set keeps only its motion along the cushion.
/// True if that changed anything.
fn hold_against_walls(g: &mut Scratch, ctx: &Ctx) -> bool {
    let r = ctx.params.ball_radius;
    let mut changed = false;
    for w in 0..g.walls.len() {
        accelerations(g, ctx);
        let (slot, normal, _) = g.walls[w];
        let s = g.states[slot];
        if s.vel.dot(normal) < HOLD_SPEED && g.acc[slot].dot(normal) < 0.0 {
            let top = root(&g.parent, slot);
            let mut vel = s.vel;
            vel -= normal * vel.dot(normal).min(0.0);
            let spin = without_normal_slip(vel, s.spin, normal, r);
            for m in 0..g.states.len() {
                let t = &mut g.states[m];
                if root(&g.parent, m) == top && (t.vel != vel || t.spin != spin) {
                    t.vel = vel;
                    t.spin = spin;
                    changed = true;
                    g.wall_acted[w] = true;
                }
            }
        }
    }
    changed
}

/// Each slot's acceleration on the cloth in its current state.
fn accelerations(g: &mut Scratch, ctx: &Ctx) {
    g.acc.clear();
    for s in &g.states {
        let mut c = *s;
        c.classify(ctx.params.ball_radius);
        g.acc.push(Piece::new(0.0, c, &ctx.motion).acc);
    }
}

pub(super) fn root(parent: &[usize], mut k: usize) -> usize {
    while parent[k] != k {
        k = parent[k];
    }
    k
}

/// Several contacts at one instant as one frictionless impact with Poisson's restitution
/// `e`: the normal impulses `λ ≥ 0` of a perfectly inelastic impact are found first (every
/// contact ends not approaching, and a contact that ends separating carries no impulse: a
/// linear complementarity problem), then every impulse is scaled by `1 + e`. Scaling the
/// inelastic solution this way never adds energy for `e ≤ 1`, keeps momentum, and treats all
/// contacts alike. The complementarity problem is solved by projected Jacobi iteration, in
/// which every contact is updated from the same velocities, so the result does not depend on
/// the order of the contacts. A held set of balls (`Scratch::parent`) moves as one body of
/// their total mass.
fn simultaneous_impact(g: &mut Scratch, e: f64) {
    /// Sweeps of the iteration before giving up on further accuracy.
    const MAX_SWEEPS: usize = 10_000;
    let n = g.states.len();
    g.lambda.clear();
    g.delta.clear();
    g.vel.clear();
    g.vel.extend(g.states.iter().map(|s| s.vel));
    // Body n, the cushions, does not move: infinite mass.
    g.vel.push(DVec2::ZERO);
    refill(&mut g.size, n, 0.0);
    for m in 0..n {
        g.size[root(&g.parent, m)] += 1.0;
    }
    g.size.push(f64::INFINITY);
    let mut fastest: f64 = 0.0;
    refill(&mut g.degree, n + 1, 0);
    g.bodies.clear();
    for (k, &(a, b)) in g.component.iter().enumerate() {
        let (a, b) = (root(&g.parent, a), root(&g.parent, b));
        g.bodies.push((a, b));
        g.lambda.push(0.0);
        g.delta.push(0.0);
        fastest = fastest.max(-(g.vel[b] - g.vel[a]).dot(g.component_normals[k]));
        g.degree[a] += 1;
        g.degree[b] += 1;
    }
    // Under-relaxation by the most contacts on one body keeps the iteration convergent.
    let omega = 1.0 / g.degree.iter().copied().max().unwrap_or(1).max(1) as f64;
    let tolerance = 1e-15 * fastest;
    for _ in 0..MAX_SWEEPS {
        let mut largest: f64 = 0.0;
        for (k, &(a, b)) in g.bodies.iter().enumerate() {
            // Separating speed, and how much each unit of impulse changes it.
            let u = (g.vel[b] - g.vel[a]).dot(g.component_normals[k]);
            let w = 1.0 / g.size[a] + 1.0 / g.size[b];
            let next = (g.lambda[k] - omega * u / w).max(0.0);
            g.delta[k] = next - g.lambda[k];
            largest = largest.max(g.delta[k].abs());
        }
        for (k, &(a, b)) in g.bodies.iter().enumerate() {
            let impulse = g.component_normals[k] * g.delta[k];
            g.vel[a] -= impulse / g.size[a];
            g.vel[b] += impulse / g.size[b];
            g.lambda[k] += g.delta[k];
        }
        if largest <= tolerance {
            break;
        }
    }
    // The impulses, scaled by 1 + e, on each body's own velocity.
    for m in 0..n {
        g.vel[m] = g.states[m].vel;
    }
    g.vel[n] = DVec2::ZERO;
    for (k, &(a, b)) in g.bodies.iter().enumerate() {
        let impulse = g.component_normals[k] * ((1.0 + e) * g.lambda[k]);
        g.vel[a] -= impulse / g.size[a];
        g.vel[b] += impulse / g.size[b];
    }
    // Members of a held set share one velocity already: they keep sharing it.
    for m in 0..n {
        g.states[m].vel = g.vel[root(&g.parent, m)];
    }
}

/// Collisions involving a ball in flight: the predicted pairs, one after the other (in
/// flight, contacts meet at one instant only by chance), with nothing held.
pub(super) fn flight_impact(g: &mut Scratch, ctx: &Ctx) {
    g.parent.clear();
    g.parent.extend(0..=g.states.len());
    refill(&mut g.acted, g.contacts.len(), true);
    g.blow.iter_mut().for_each(|b| *b = 0.0);
    g.wall_acted.clear();
    for k in 0..g.contacts.len() {
        let (a, b) = g.contacts[k];
        collide_pair(&mut g.states, a, b, ctx);
    }
}

/// One contact approaching on its own, by the pairwise collision model.
fn collide_pair(states: &mut [BallState], a: usize, b: usize, ctx: &Ctx) {
    let (sa, sb) = (states[a], states[b]);
    if sa.motion == MotionState::Airborne || sb.motion == MotionState::Airborne {
        let friction =
            ctx.models.ball_ball == BallBallModel::Frictional && ctx.effects.ball_friction;
        airborne::collide(states, a, b, restitution(ctx), friction, ctx.params);
        return;
    }
    let (ka, kb) = ball_ball::collide(
        sa.pos,
        sb.pos,
        Kinematics {
            vel: sa.vel,
            spin: sa.spin,
        },
        Kinematics {
            vel: sb.vel,
            spin: sb.spin,
        },
        ctx.models.ball_ball,
        ctx.effects.ball_friction,
        ctx.params,
    );
    states[a].vel = ka.vel;
    states[a].spin = ka.spin;
    states[b].vel = kb.vel;
    states[b].spin = kb.spin;
}

/// The spin that leaves the ball's cloth slip with no component along `n`, changing only the
/// spin about the horizontal axis across `n`.
pub(super) fn without_normal_slip(vel: DVec2, spin: DVec3, n: DVec2, r: f64) -> DVec3 {
    // slip·n = v·n − R·(ω·t) with t = (−n_y, n_x).
    let t = DVec2::new(-n.y, n.x);
    let current = spin.x * t.x + spin.y * t.y;
    let target = vel.dot(n) / r;
    let d = target - current;
    DVec3::new(spin.x + d * t.x, spin.y + d * t.y, spin.z)
}
