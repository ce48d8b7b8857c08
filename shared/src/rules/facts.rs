//! What a shot did, as the rules see it, read from the physics outcome.

use serde::{Deserialize, Serialize};

use crate::physics::{ball_cushion, Cushion, EventKind, Outcome, Params, Table, TableKind};

use super::rack;

/// The cue ball's number (and index in the ball list).
pub const CUE: u8 = 0;

/// How close to a cushion (m) a ball counts as touching it ("frozen"). Racked and placed
/// balls are exact to far better than this; a ball that has left a rail is further away.
const FROZEN: f64 = 1e-6;

/// A ball that left the table (WPA 8.5 "driven off the table"), and when.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Departure {
    /// The ball's number.
    pub ball: u8,
    /// Seconds after the strike.
    pub t: f64,
}

/// The balls that left the table during `outcome`, in time order.
///
/// This is the one place the rules learn that a ball left the table: everything the rules
/// say about it follows from the list. The engine reports it as a `ball_off_table` event
/// (a ball jumped over a rail by an elevated cue).
pub fn departures(outcome: &Outcome) -> Vec<Departure> {
    outcome
        .events
        .iter()
        .filter_map(|e| match e.kind {
            EventKind::BallOffTable { ball } => Some(Departure {
                ball: ball as u8,
                t: e.t,
            }),
            _ => None,
        })
        .collect()
}

/// The facts of one shot that the rules judge.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShotFacts {
    /// The first ball the cue ball touched, if any.
    pub first_contact: Option<u8>,
    /// Some ball (the cue ball included) was driven to a rail (WPA 8.4: it touched a
    /// cushion it was not already touching, or left the table) after the first contact.
    pub cushion_after_contact: bool,
    /// Object balls driven to a rail (WPA 8.4) at any time in the shot, each once, in order;
    /// balls that left the table count.
    pub object_balls_to_cushion: Vec<u8>,
    /// Balls that fell, with the pocket, in the order they fell (the cue ball included).
    pub pocketed: Vec<(u8, u8)>,
    /// Balls that left the table, in the order they left (see [`departures`]).
    pub off_table: Vec<u8>,
    /// The first ball the cue ball touched lay behind the head string, and the cue ball had
    /// not crossed the head string before touching it (WPA 6.11; a foul only for a shot
    /// taken with the cue ball in hand behind the head string).
    pub contact_behind_head_string: bool,
}

impl ShotFacts {
    /// Reads the facts from a shot simulated on `kind` whose ball indices are ball numbers.
    pub fn from_outcome(outcome: &Outcome, kind: TableKind) -> ShotFacts {
        ShotFacts::read(outcome, kind, &departures(outcome))
    }

    /// Reads the facts from a shot in which the balls of `left` left the table.
    pub fn read(outcome: &Outcome, kind: TableKind, left: &[Departure]) -> ShotFacts {
        let table = Table::new(kind);
        let mut facts = ShotFacts::default();
        let mut contact_time = None;
        let mut departures = left.to_vec();
        departures.sort_by(|a, b| a.t.total_cmp(&b.t));
        // When each ball last took part in an event: a ball touching a cushion then and
        // midway to now never left it.
        let mut last_event = vec![0.0; outcome.history.len()];
        for event in &outcome.events {
            match event.kind {
                EventKind::BallBall { a, b } => {
                    if facts.first_contact.is_none() {
                        if a == u16::from(CUE) {
                            facts.first_contact = Some(b as u8);
                        } else if b == u16::from(CUE) {
                            facts.first_contact = Some(a as u8);
                        }
                        if facts.first_contact.is_some() {
                            contact_time = Some(event.t);
                        }
                    }
                }
                EventKind::BallCushion { ball, cushion } => {
                    let since = last_event.get(usize::from(ball)).copied().unwrap_or(0.0);
                    if !stayed_on(outcome, &table, usize::from(ball), cushion, since, event.t) {
                        facts.driven(ball as u8);
                    }
                }
                EventKind::BallPocket { ball, pocket } => facts.pocketed.push((ball as u8, pocket)),
                EventKind::Strike { .. }
                | EventKind::Transition { .. }
                | EventKind::BallTable { .. }
                | EventKind::BallOffTable { .. } => {}
            }
            let (balls, n) = event.kind.balls();
            for &b in &balls[..n] {
                if let Some(t) = last_event.get_mut(usize::from(b)) {
                    *t = event.t;
                }
            }
        }
        // A ball that leaves the table was driven to a rail (WPA 8.4).
        for d in &departures {
            if !facts.off_table.contains(&d.ball) {
                facts.off_table.push(d.ball);
            }
            if contact_time.is_some_and(|c| d.t >= c) {
                facts.cushion_after_contact = true;
            }
            if d.ball != CUE && !facts.object_balls_to_cushion.contains(&d.ball) {
                facts.object_balls_to_cushion.push(d.ball);
            }
        }
        if let (Some(ball), Some(t)) = (facts.first_contact, contact_time) {
            facts.contact_behind_head_string = behind_head_string(outcome, kind, ball, t);
        }
        facts
    }

    /// `ball` was driven to a rail now.
    fn driven(&mut self, ball: u8) {
        if self.first_contact.is_some() {
            self.cushion_after_contact = true;
        }
        if ball != CUE && !self.object_balls_to_cushion.contains(&ball) {
            self.object_balls_to_cushion.push(ball);
        }
    }

    /// The cue ball fell in a pocket or left the table.
    pub fn scratched(&self) -> bool {
        self.fell(CUE) || self.off_table.contains(&CUE)
    }

    /// `ball` fell in a pocket.
    pub fn fell(&self, ball: u8) -> bool {
        self.pocketed.iter().any(|&(b, _)| b == ball)
    }

    /// `ball` fell in a pocket or left the table.
    pub fn gone(&self, ball: u8) -> bool {
        self.fell(ball) || self.off_table.contains(&ball)
    }

    /// The pocket `ball` fell into.
    pub fn pocket_of(&self, ball: u8) -> Option<u8> {
        self.pocketed
            .iter()
            .find(|&&(b, _)| b == ball)
            .map(|&(_, p)| p)
    }

    /// Object balls that fell, in order.
    pub fn object_balls_pocketed(&self) -> impl Iterator<Item = u8> + '_ {
        self.pocketed.iter().map(|&(b, _)| b).filter(|&b| b != CUE)
    }

    /// Object balls that left the table, in order.
    pub fn object_balls_off_table(&self) -> impl Iterator<Item = u8> + '_ {
        self.off_table.iter().copied().filter(|&b| b != CUE)
    }

    /// Some object ball fell.
    pub fn any_object_ball_pocketed(&self) -> bool {
        self.object_balls_pocketed().next().is_some()
    }

    /// The common foul of a shot that hits a ball but sends nothing to a pocket or a cushion.
    pub fn no_cushion_after_contact(&self) -> bool {
        self.first_contact.is_some() && !self.cushion_after_contact && self.pocketed.is_empty()
    }
}

/// How far the centre of `ball` is from touching `cushion` at time `t` (0 = touching).
fn gap(outcome: &Outcome, table: &Table, ball: usize, cushion: Cushion, t: f64) -> f64 {
    let params = Params::default();
    let p = table.to_engine(outcome.state_at(ball, t).pos);
    match cushion {
        Cushion::Rail(i) => table.rails.get(usize::from(i)).map_or(f64::INFINITY, |r| {
            r.normal.dot(p - r.a) - ball_cushion::contact_distance(&params)
        }),
        Cushion::Jaw(i) => table.jaws.get(usize::from(i)).map_or(f64::INFINITY, |j| {
            (p - j.center).length() - j.radius - ball_cushion::contact_distance(&params)
        }),
    }
}

/// Did `ball`, which meets `cushion` at `t`, stay on it since `since` (its last event)?
/// Between two events a ball follows one closed-form piece, along which its distance from
/// a rail is a quadratic in time: equal at both ends, it is furthest midway, so touching at
/// `since` and midway means it never left (WPA 8.4: a frozen ball pressed into its rail is
/// not driven to it).
fn stayed_on(
    outcome: &Outcome,
    table: &Table,
    ball: usize,
    cushion: Cushion,
    since: f64,
    t: f64,
) -> bool {
    let touching = |at: f64| gap(outcome, table, ball, cushion, at) <= FROZEN;
    touching(since) && touching(0.5 * (since + t))
}

/// Was `ball` (hit first at `t`) behind the head string, with the cue ball never across it
/// before `t`? Before the first contact only the cue ball moves, so `ball` is where it
/// started; the cue ball's pieces are parabolas, whose furthest point up the table is at an
/// end or at the vertex.
fn behind_head_string(outcome: &Outcome, kind: TableKind, ball: u8, t: f64) -> bool {
    let head = rack::head_string(kind);
    if outcome.state_at(usize::from(ball), 0.0).pos.y >= head {
        return false;
    }
    let Some(pieces) = outcome.history.get(usize::from(CUE)) else {
        return false;
    };
    let crossed = pieces.iter().filter(|p| p.t0 < t).any(|p| {
        let end = p.t_end.min(t);
        let mut times = vec![p.t0, end];
        if p.acc.y != 0.0 {
            let vertex = p.t0 - p.start.vel.y / p.acc.y;
            if vertex > p.t0 && vertex < end {
                times.push(vertex);
            }
        }
        times
            .into_iter()
            .any(|at| outcome.state_at(usize::from(CUE), at).pos.y >= head)
    });
    !crossed
}
