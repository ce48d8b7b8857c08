//! Fixed-step integration, as games and the founding paper (Leckie & Greenspan 2005) do it:
//! advance every ball by `dt` with the motion equations of its current state, then look for
//! overlaps at the end of the step and resolve them. Optionally each overlapping pair (or
//! ball and cushion) is first backed up to its time of impact, resolved there, and carried
//! forward again for the rest of the step.
//!
//! The motion over a step uses the engine's closed form for the state the ball was in at the
//! start of the step (the same friction model: sliding, rolling, spin), so within a step the
//! only approximation is that a change of state (sliding to rolling, rolling to rest) is
//! noticed at the end of the step, not when it happens. Collisions use the engine's own
//! resolution functions (ball–ball and cushion models), so any difference from the engine
//! comes from stepping alone. Cushions are the straight rails and the round jaws of
//! [`Table`]; a ball whose centre is inside a pocket's capture circle falls.

use breakshot_shared::physics::ball_ball::{collide, Kinematics};
use breakshot_shared::physics::ball_cushion::{bounce, model_contact_distance};
use breakshot_shared::physics::engine::check;
use breakshot_shared::physics::motion::MotionModel;
use breakshot_shared::physics::{BallState, MotionState, Piece, Shot, ShotError, Table};
use glam::{DVec2, DVec3};

use super::trace::{Contact, Trace};

/// Longest simulated time when the shot has no horizon: far beyond any shot's rest time.
pub const MAX_TIME: f64 = 120.0;

/// A fixed-step method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedStep {
    /// The step (s).
    pub dt: f64,
    /// Back overlapping pairs up to their contact time before resolving them.
    pub toi: bool,
}

/// What a fixed-step run gives besides its trace.
#[derive(Clone, Debug, Default)]
pub struct StepRun {
    pub trace: Trace,
    pub steps: u64,
    /// The deepest overlap of two balls at the moment it was detected (m).
    pub deepest_overlap: f64,
    /// Balls that went through a cushion or past a pocket and left the table; each is
    /// stopped where it was found (it would be on the floor).
    pub escaped: usize,
}

/// How far beyond the cushion noses a ball's centre must be to have left the table: well
/// past the back of every pocket's capture circle (m).
pub const ESCAPE_MARGIN: f64 = 0.15;

/// A contact found at the end of a step.
#[derive(Clone, Copy, Debug)]
struct Found {
    /// How long before the end of the step the contact began (0 without TOI correction).
    back: f64,
    what: Touch,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Touch {
    Balls(usize, usize),
    /// A cushion with its inward normal, or a jaw (normal from the jaw's axis to the ball).
    Rail(usize, usize),
    Jaw(usize, usize),
}

/// Simulates `shot` with fixed steps.
pub fn simulate(shot: &Shot, method: FixedStep) -> Result<StepRun, ShotError> {
    check(shot)?;
    let mut sim = Stepper::new(shot, method)?;
    let end = shot.horizon.unwrap_or(MAX_TIME);
    let mut t = 0.0;
    while t < end && sim.any_moving() {
        let h = method.dt.min(end - t);
        sim.step(h);
        t += h;
    }
    Ok(sim.finish())
}

struct Stepper<'a> {
    shot: &'a Shot,
    method: FixedStep,
    table: Table,
    model: MotionModel,
    contact: f64,
    balls: Vec<BallState>,
    run: StepRun,
    found: Vec<Found>,
}

impl<'a> Stepper<'a> {
    fn new(shot: &'a Shot, method: FixedStep) -> Result<Self, ShotError> {
        let table = Table::new(shot.table);
        let r = shot.params.ball_radius;
        let mut balls: Vec<BallState> = shot
            .balls
            .iter()
            .map(|b| {
                let mut s = *b;
                s.pos = table.to_engine(s.pos);
                s.classify(r);
                s
            })
            .collect();
        if let Some((i, strike)) = shot.strike {
            let (v, w) = strike.ball_motion(&shot.params)?;
            balls[i].vel = v;
            balls[i].spin = w;
            balls[i].classify(r);
        }
        Ok(Stepper {
            shot,
            method,
            model: MotionModel::new(&shot.params, &shot.effects),
            contact: model_contact_distance(&shot.params, shot.models.cushion),
            table,
            balls,
            run: StepRun::default(),
            found: Vec::new(),
        })
    }

    fn radius(&self) -> f64 {
        self.shot.params.ball_radius
    }

    fn any_moving(&self) -> bool {
        self.balls.iter().any(|b| b.motion.is_translating())
    }

    fn step(&mut self, h: f64) {
        self.run.steps += 1;
        let r = self.radius();
        for b in &mut self.balls {
            *b = advance(*b, h, &self.model, r);
        }
        self.pockets();
        self.escapes();
        self.find_contacts(h);
        self.resolve_contacts();
    }

    /// A ball whose centre is inside a capture circle falls.
    fn pockets(&mut self) {
        if !self.shot.effects.pockets {
            return;
        }
        for (i, b) in self.balls.iter_mut().enumerate() {
            if !b.motion.is_translating() {
                continue;
            }
            if let Some(k) = self
                .table
                .pockets
                .iter()
                .position(|p| (b.pos - p.center).length() < p.radius)
            {
                b.vel = DVec2::ZERO;
                b.spin = DVec3::ZERO;
                b.motion = MotionState::Pocketed;
                b.pocket = Some(k as u8);
                self.run
                    .trace
                    .contacts
                    .push(Contact::Pocket(i as u16, k as u8));
            }
        }
    }

    /// A ball that tunnelled out of the table stops there.
    fn escapes(&mut self) {
        if !self.shot.effects.cushions || !self.table.has_cushions() {
            return;
        }
        let limit = self.table.half + DVec2::splat(ESCAPE_MARGIN);
        for b in &mut self.balls {
            if b.motion.is_translating() && (b.pos.x.abs() > limit.x || b.pos.y.abs() > limit.y) {
                *b = BallState::at_rest(b.pos);
                self.run.escaped += 1;
            }
        }
    }

    /// Every overlap at the end of a step of length `h` whose two sides approach.
    fn find_contacts(&mut self, h: f64) {
        self.found.clear();
        let diameter = 2.0 * self.radius();
        let n = self.balls.len();
        for i in 0..n {
            let a = self.balls[i];
            if a.motion == MotionState::Pocketed {
                continue;
            }
            for j in i + 1..n {
                let b = self.balls[j];
                if b.motion == MotionState::Pocketed
                    || !(a.motion.is_translating() || b.motion.is_translating())
                {
                    continue;
                }
                let d = b.pos - a.pos;
                let dv = b.vel - a.vel;
                if d.length_squared() < diameter * diameter && d.dot(dv) < 0.0 {
                    self.run.deepest_overlap = self.run.deepest_overlap.max(diameter - d.length());
                    let back = self.back_up(time_since_circle(d, dv, diameter), h);
                    self.found.push(Found {
                        back,
                        what: Touch::Balls(i, j),
                    });
                }
            }
        }
        if !self.shot.effects.cushions {
            return;
        }
        for (i, b) in self.balls.iter().enumerate() {
            if !b.motion.is_translating() {
                continue;
            }
            for (k, rail) in self.table.rails.iter().enumerate() {
                let depth = self.contact - rail.normal.dot(b.pos - rail.a);
                let inward = -rail.normal.dot(b.vel);
                let along = rail.b - rail.a;
                let s = along.dot(b.pos - rail.a);
                if depth > 0.0 && inward > 0.0 && s >= 0.0 && s <= along.dot(along) {
                    let back = self.back_up(depth / inward, h);
                    self.found.push(Found {
                        back,
                        what: Touch::Rail(i, k),
                    });
                }
            }
            for (k, jaw) in self.table.jaws.iter().enumerate() {
                let d = b.pos - jaw.center;
                let reach = jaw.radius + self.contact;
                if d.length_squared() < reach * reach && d.dot(b.vel) < 0.0 {
                    let back = self.back_up(time_since_circle(d, b.vel, reach), h);
                    self.found.push(Found {
                        back,
                        what: Touch::Jaw(i, k),
                    });
                }
            }
        }
    }

    /// How far to back a contact up: to its contact time with the correction (never before
    /// the start of the step), not at all without.
    fn back_up(&self, since: f64, h: f64) -> f64 {
        if self.method.toi {
            since.clamp(0.0, h)
        } else {
            0.0
        }
    }

    /// Resolves the contacts found, earliest first (in detection order without the
    /// correction); one that an earlier resolution already separated is skipped.
    fn resolve_contacts(&mut self) {
        let mut found = std::mem::take(&mut self.found);
        // Earliest contact = backed up the most; the sort is stable for ties.
        found.sort_by(|x, y| y.back.total_cmp(&x.back));
        for f in &found {
            self.resolve(*f);
        }
        self.found = found;
    }

    fn resolve(&mut self, f: Found) {
        let r = self.radius();
        let p = &self.shot.params;
        let s = f.back;
        match f.what {
            Touch::Balls(i, j) => {
                let (a, b) = (self.balls[i], self.balls[j]);
                // Straight-line motion over the part of the step being undone.
                let (pa, pb) = (a.pos - a.vel * s, b.pos - b.vel * s);
                if (pb - pa).dot(b.vel - a.vel) >= 0.0 {
                    return;
                }
                let kin = |x: &BallState| Kinematics {
                    vel: x.vel,
                    spin: x.spin,
                };
                let (ka, kb) = collide(
                    pa,
                    pb,
                    kin(&a),
                    kin(&b),
                    self.shot.models.ball_ball,
                    self.shot.effects.ball_friction,
                    p,
                );
                for (idx, old, at, k) in [(i, a, pa, ka), (j, b, pb, kb)] {
                    let mut n = old;
                    n.pos = at + k.vel * s;
                    n.vel = k.vel;
                    n.spin = k.spin;
                    n.classify(r);
                    self.balls[idx] = n;
                }
                self.run
                    .trace
                    .contacts
                    .push(Contact::Balls(i as u16, j as u16));
            }
            Touch::Rail(i, k) => {
                let normal = self.table.rails[k].normal;
                self.bounce(i, normal, s);
            }
            Touch::Jaw(i, k) => {
                let b = self.balls[i];
                let normal = (b.pos - b.vel * s - self.table.jaws[k].center).normalize_or_zero();
                self.bounce(i, normal, s);
            }
        }
    }

    fn bounce(&mut self, i: usize, normal: DVec2, s: f64) {
        let b = self.balls[i];
        if b.vel.dot(normal) >= 0.0 {
            return;
        }
        let at = b.pos - b.vel * s;
        let (v, w) = bounce(
            b.vel,
            b.spin,
            normal,
            self.shot.models.cushion,
            &self.shot.params,
        );
        let mut n = b;
        n.pos = at + v * s;
        n.vel = v;
        n.spin = w;
        n.classify(self.radius());
        self.balls[i] = n;
        self.run.trace.contacts.push(Contact::Cushion(i as u16));
    }

    fn finish(mut self) -> StepRun {
        for b in &self.balls {
            let pocket = (b.motion == MotionState::Pocketed)
                .then_some(b.pocket)
                .flatten();
            let pos = self.table.to_scene(b.pos);
            self.run.trace.push_final(&self.table, pos, pocket);
        }
        self.run
    }
}

/// Advances one ball by `h` in the motion of the state it is in. A change of state inside
/// the step is noticed only at its end: a sliding ball then rolls (its spin set to match its
/// velocity), a rolling ball stops where it is, a spinning ball stops spinning.
pub fn advance(s: BallState, h: f64, model: &MotionModel, radius: f64) -> BallState {
    if matches!(s.motion, MotionState::Stationary | MotionState::Pocketed) {
        return s;
    }
    let piece = Piece::new(0.0, s, model);
    let mut next = piece.state_at(h, radius);
    if piece.t_end <= h {
        match s.motion {
            MotionState::Sliding => {
                next.spin.x = -next.vel.y / radius;
                next.spin.y = next.vel.x / radius;
                next.classify(radius);
                if next.motion == MotionState::Sliding {
                    next.motion = MotionState::Rolling;
                }
            }
            MotionState::Rolling => {
                next.vel = DVec2::ZERO;
                next.spin.x = 0.0;
                next.spin.y = 0.0;
                next.classify(radius);
            }
            _ => {
                next.spin = DVec3::ZERO;
                next.motion = MotionState::Stationary;
            }
        }
    }
    next
}

/// How long ago a point at offset `d` moving at relative velocity `dv` (approaching) entered
/// the circle of radius `reach` about the origin, in straight-line motion.
pub fn time_since_circle(d: DVec2, dv: DVec2, reach: f64) -> f64 {
    // |d − dv·s|² = reach² for the positive root s (going back in time).
    let a = dv.length_squared();
    if a == 0.0 {
        return 0.0;
    }
    let b = d.dot(dv);
    let c = (d.length() - reach) * (d.length() + reach);
    let disc = (b * b - a * c).max(0.0);
    (b + disc.sqrt()) / a
}

#[cfg(test)]
mod tests {
    use super::*;
    use breakshot_shared::physics::{
        simulate as exact, BallBallModel, Effects, Models, Params, Strike, TableKind,
    };

    fn open_shot(balls: Vec<BallState>, strike: Option<(usize, Strike)>) -> Shot {
        Shot {
            table: TableKind::Open,
            params: Params::default(),
            models: Models {
                ball_ball: BallBallModel::Ideal,
                ..Models::default()
            },
            effects: Effects::default(),
            horizon: None,
            balls,
            strike,
        }
    }

    /// `shot` stepped by `dt` (s), with or without the time-of-impact correction.
    fn stepped(shot: &Shot, dt: f64, toi: bool) -> StepRun {
        simulate(shot, FixedStep { dt, toi }).expect("the shot steps")
    }

    #[test]
    fn single_ball_converges_to_the_exact_final_position() {
        let strike = Strike::at_angle(3.0, 30.0, DVec2::new(0.2, -0.3));
        let shot = open_shot(vec![BallState::at_rest(DVec2::ZERO)], Some((0, strike)));
        let reference = exact(&shot).unwrap().finals[0].pos;
        // The slide ends inside a step at a point that varies with dt, so the error is not
        // monotone in dt, but it is bounded by a constant times dt (the sliding overshoot of
        // one step, then amplified by the long roll): first order.
        let steps = [1.0 / 60.0, 1e-3, 1e-4, 1e-5];
        let errors: Vec<f64> = steps
            .iter()
            .map(|&dt| {
                let run = stepped(&shot, dt, false);
                (run.trace.finals[0] - reference).length()
            })
            .collect();
        for (dt, e) in steps.iter().zip(&errors) {
            assert!(*e <= 40.0 * dt, "dt {dt}: {e} m");
        }
        assert!(errors[0] > 0.05, "a 60 Hz step is visibly off: {errors:?}");
        assert!(errors[3] < 1e-3, "{errors:?}");
    }

    #[test]
    fn time_of_impact_of_two_balls_in_straight_line_motion_is_exact() {
        // Frictionless, so motion is straight; ball 0 heads for ball 1 at 2 m/s along x.
        let r = Params::default().ball_radius;
        let gap = 0.1;
        let mut balls = vec![
            BallState::moving(DVec2::ZERO, DVec2::new(2.0, 0.0), DVec3::ZERO, r),
            BallState::at_rest(DVec2::new(2.0 * r + gap, 0.0)),
        ];
        balls[0].spin = DVec3::new(0.0, 2.0 / r, 0.0);
        balls[0].classify(r);
        let mut shot = open_shot(balls, None);
        shot.effects = Effects::none();
        shot.horizon = Some(0.2);
        // Contact at t = 0.05 s; a step of 0.03 s finds the overlap at 0.06 s.
        let run = stepped(&shot, 0.03, true);
        // Exchanged at the contact time: ball 0 stops at gap, ball 1 moves on for 0.15 s.
        let end = run.trace.finals.clone();
        assert!((end[0].x - gap).abs() < 1e-12, "{end:?}");
        assert!(
            (end[1].x - (2.0 * r + gap + 2.0 * 0.15)).abs() < 1e-12,
            "{end:?}"
        );
        // Without the correction the exchange happens 0.01 s late, 2 cm deeper.
        let late = stepped(&shot, 0.03, false).trace.finals;
        assert!((late[0].x - (gap + 0.02)).abs() < 1e-12, "{late:?}");
        assert_eq!(run.trace.contacts, vec![Contact::Balls(0, 1)]);
    }

    #[test]
    fn contact_time_of_a_circle_is_exact() {
        // A point 0.5 inside a circle of radius 1 on the x axis, having come in along x at 2.
        let since = time_since_circle(DVec2::new(-0.5, 0.0), DVec2::new(2.0, 0.0), 1.0);
        assert!((since - 0.25).abs() < 1e-15, "{since}");
    }

    #[test]
    fn a_sixty_hertz_step_tunnels_through_a_ball_at_break_speed() {
        let r = Params::default().ball_radius;
        let balls = vec![
            BallState::at_rest(DVec2::ZERO),
            BallState::at_rest(DVec2::new(0.0, 0.3)),
        ];
        // 12 m/s: 0.2 m per step at 60 Hz, more than three ball diameters.
        let strike = Strike::at_angle(8.0, 90.0, DVec2::ZERO);
        let shot = open_shot(balls, Some((0, strike)));
        let coarse = stepped(&shot, 1.0 / 60.0, true);
        let fine = stepped(&shot, 1e-4, true);
        assert!(
            !coarse.trace.contacts.contains(&Contact::Balls(0, 1)),
            "tunnelled"
        );
        assert!(fine.trace.contacts.contains(&Contact::Balls(0, 1)));
        assert!(fine.deepest_overlap < 2.0 * r);
    }

    #[test]
    fn a_ball_is_reflected_by_a_rail_and_can_be_pocketed() {
        let table = Table::new(TableKind::NineFoot);
        let mut shot = open_shot(vec![BallState::at_rest(DVec2::new(0.635, 1.27))], None);
        shot.table = TableKind::NineFoot;
        // Straight at the middle of the x = width rail (the right side pocket is at y = l/2,
        // so aim a little off it), then straight into the bottom-left corner pocket.
        shot.strike = Some((0, Strike::at_angle(2.0, 10.0, DVec2::ZERO)));
        let run = stepped(&shot, 1e-4, true);
        assert_eq!(run.trace.contacts.first(), Some(&Contact::Cushion(0)));
        let corner = table.to_scene(table.pockets[0].center);
        shot.balls[0] = BallState::at_rest(corner + DVec2::new(0.3, 0.3));
        shot.strike = Some((0, Strike::at_angle(2.0, 225.0, DVec2::ZERO)));
        let run = stepped(&shot, 1e-3, false);
        assert_eq!(run.trace.pockets[0], Some(0));
        assert_eq!(run.trace.finals[0], corner);
    }
}
