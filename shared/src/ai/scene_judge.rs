//! The player on a bare scene: the best strike for the cue ball that hits one of a set of
//! target balls first and pockets one of them, with its chance under the level's noise
//! (`breakshot-sim suggest`).

use super::candidates::{generate, Kind, View};
use super::geometry::Layout;
use super::lab::Lab;
use super::noise::mix;
use super::search::{choose, Judge, Played};
use super::thinking::{Meter, Thinking};
use super::{estimate, Level, Player};
use crate::physics::{BallState, MotionState, Shot, Strike};
use crate::rules::facts::ShotFacts;

/// What [`Thinking::suggest`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Suggestion {
    /// The strike on the cue ball the search was asked about.
    pub strike: Strike,
    /// Share of the trials under the level's noise that succeeded.
    pub p_success: f64,
    /// What the search took the shot for (a pot, a bank, a safety, ...).
    pub kind: Kind,
}

impl Thinking<Result<Suggestion, String>> {
    /// The best strike on ball `cue` of `shot` that first hits one of `targets` and pockets
    /// one of them (ball indices into `shot.balls`), as a search in steps; `.finish()` runs it
    /// in one call. Errors name what is wrong with the request.
    pub fn suggest(
        shot: &Shot,
        cue: usize,
        targets: &[usize],
        level: Level,
        seed: u64,
    ) -> Thinking<Result<Suggestion, String>> {
        let shot = shot.clone();
        let targets = targets.to_vec();
        Thinking::start(move |meter| async move {
            suggested(&shot, cue, &targets, level, seed, &meter).await
        })
    }
}

/// What [`Thinking::suggest`] answers, its simulations counted on `meter`.
async fn suggested(
    shot: &Shot,
    cue: usize,
    targets: &[usize],
    level: Level,
    seed: u64,
    meter: &Meter,
) -> Result<Suggestion, String> {
    let n = shot.balls.len();
    if cue >= n {
        return Err("the scene has no cue ball".into());
    }
    if n > usize::from(u8::MAX) {
        return Err("too many balls".into());
    }
    if targets.is_empty() || targets.iter().any(|&t| t >= n || t == cue) {
        return Err("--targets must name object balls of the scene".into());
    }
    // Renumber so that the cue ball is ball 0, as in a game.
    let order: Vec<usize> = std::iter::once(cue)
        .chain((0..n).filter(|&i| i != cue))
        .collect();
    let number = |i: usize| order.iter().position(|&o| o == i).unwrap_or(0) as u8;
    let balls: Vec<BallState> = order.iter().map(|&i| shot.balls[i]).collect();
    let targets: Vec<u8> = targets.iter().map(|&t| number(t)).collect();
    if balls[0].motion == MotionState::Pocketed {
        return Err("the cue ball is not on the table".into());
    }
    let renumbered = Shot {
        balls,
        strike: None,
        ..shot.clone()
    };
    let player = Player::from(level);
    let layout = Layout::new(renumbered.table, &renumbered.balls);
    let view = View {
        layout: &layout,
        targets: &targets,
        pottable: &targets,
        aim_sigma: player.noise.aim_sigma(),
    };
    meter.expect(estimate::shot(&player.breadth, &player.schedule, 0));
    let mut lab = Lab::new(renumbered.clone(), meter);
    let candidates = generate(&mut lab, &view, &player.breadth).await;
    let mut judge = SceneJudge {
        lab: Lab::new(renumbered, meter),
        targets: &targets,
        aim_sigma: player.noise.aim_sigma(),
        meter,
    };
    let choice = choose(
        &mut judge,
        &candidates,
        player.noise,
        &player.schedule,
        mix(seed, 0x5CE0),
    )
    .await
    .ok_or("no strike could be found for this scene")?;
    Ok(Suggestion {
        strike: choice.candidate.strike,
        p_success: choice.p_success,
        kind: choice.candidate.kind,
    })
}

struct SceneJudge<'a> {
    lab: Lab,
    targets: &'a [u8],
    aim_sigma: f64,
    meter: &'a Meter,
}

impl Judge for SceneJudge<'_> {
    async fn play(&mut self, strike: &Strike, _call: Option<u8>, _deep: bool) -> Played {
        let kind = self.lab_kind();
        let Some(out) = self.lab.strike(0, *strike).await else {
            return Played::REFUSED;
        };
        let facts = ShotFacts::from_outcome(out, kind);
        let finals = out.finals.clone();
        let hit = facts
            .first_contact
            .is_some_and(|b| self.targets.contains(&b));
        let potted = facts
            .object_balls_pocketed()
            .any(|b| self.targets.contains(&b));
        let success = hit && potted && !facts.scratched();
        let layout = Layout::new(kind, &finals);
        let left: Vec<u8> = self
            .targets
            .iter()
            .copied()
            .filter(|&t| finals[usize::from(t)].motion != MotionState::Pocketed)
            .collect();
        let next = match layout.cue() {
            Some(cue) if !left.is_empty() => layout.best_pot(cue, &left, self.aim_sigma),
            _ => 0.0,
        };
        let value = if success {
            0.6 + 0.4 * next
        } else if facts.scratched() {
            0.0
        } else if !hit {
            0.1
        } else {
            0.5 - 0.4 * next
        };
        Played { value, success }
    }

    fn meter(&self) -> &Meter {
        self.meter
    }

    fn look_ahead_guess(&self) -> usize {
        0
    }
}

impl SceneJudge<'_> {
    fn lab_kind(&self) -> crate::physics::TableKind {
        self.lab.table()
    }
}
