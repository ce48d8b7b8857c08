//! Trial shots judged by the real rules: a trial is `Game::apply` on a copy of the game.

use super::candidates::{generate, Breadth, View};
use super::geometry::Layout;
use super::lab::Lab;
use super::noise::{Noise, Rng};
use super::search::{Judge, Played};
use super::thinking::Meter;
use super::value;
use super::Player;
use crate::physics::{MotionState, Strike};
use crate::rules::{Command, Game, Phase, Seat, Variant, Verdict};

/// The shots the look-ahead considers from the position a trial leaves.
const LOOK_AHEAD: Breadth = Breadth {
    pots: 2,
    speeds: 1,
    side: false,
    banks: false,
    combinations: false,
    kicks: false,
    safeties: false,
    corrections: 2,
};
/// Trials per look-ahead shot.
const LOOK_AHEAD_TRIALS: u64 = 2;
/// Simulations a look-ahead on a pool table typically costs (its candidates, then their
/// trials): only for the progress estimate.
const LOOK_AHEAD_GUESS: usize = 70;

pub(super) struct GameJudge<'a> {
    game: &'a Game,
    me: Seat,
    noise: Noise,
    meter: &'a Meter,
}

impl<'a> GameJudge<'a> {
    pub(super) fn new(game: &'a Game, player: &Player, meter: &'a Meter) -> GameJudge<'a> {
        GameJudge {
            game,
            me: game.to_move(),
            noise: player.noise,
            meter,
        }
    }

    /// The shooter keeps the table after `g` with the cue ball where it lies: the best of a
    /// few pots from there, each tried a couple of times.
    async fn look_ahead(&mut self, g: &Game) -> f64 {
        let sigma = self.noise.aim_sigma();
        let layout = Layout::new(g.table(), g.balls());
        let targets = g.legal_first_balls();
        let pottable = value::pottable(g);
        let view = View {
            layout: &layout,
            targets: &targets,
            pottable: &pottable,
            aim_sigma: sigma,
        };
        let Some(cue) = g.balls().first().copied() else {
            return value::value(g, self.me, sigma);
        };
        let probe = Strike {
            speed: 1.0,
            dir: glam::DVec2::Y,
            tip: glam::DVec2::ZERO,
            elevation_deg: 0.0,
        };
        let mut lab = Lab::new(g.shot_for(&probe), self.meter);
        let candidates: Vec<_> = generate(&mut lab, &view, &LOOK_AHEAD)
            .await
            .into_iter()
            .filter(|c| c.kind == super::Kind::Pot)
            .collect();
        let stay = value::value(g, self.me, sigma);
        let mut best = f64::NEG_INFINITY;
        let seed = crate::hash::state_hash(g.balls()) ^ u64::from(cue.pos.x.to_bits() as u32);
        for c in &candidates {
            let mut sum = 0.0;
            for k in 0..LOOK_AHEAD_TRIALS {
                let mut rng = Rng::new(super::noise::mix(seed, k + 1));
                let strike = self.noise.perturb(&c.strike, &mut rng);
                sum += self.play_once(g, &strike, c.call).await.value;
            }
            best = best.max(sum / LOOK_AHEAD_TRIALS as f64);
        }
        // With no pot in view the player still has the safeties the static value assumes.
        if best.is_finite() {
            best.max(0.5 * stay)
        } else {
            stay
        }
    }

    /// `strike` played by `seat` on a copy of `game`, counted as a run: the game after it and
    /// the verdict, or None if the rules refuse it.
    async fn trial(
        &mut self,
        game: &Game,
        seat: Seat,
        strike: &Strike,
        call: Option<u8>,
    ) -> Option<(Game, Verdict)> {
        self.meter.simulation().await;
        let mut g = game.clone();
        let shot = Command::Shot {
            strike: *strike,
            call,
        };
        let verdict = g.apply(seat, &shot).ok()?;
        Some((g, verdict))
    }

    async fn play_once(&mut self, game: &Game, strike: &Strike, call: Option<u8>) -> Played {
        let shooter = game.to_move();
        let Some((g, verdict)) = self.trial(game, shooter, strike, call).await else {
            return Played::REFUSED;
        };
        let sigma = self.noise.aim_sigma();
        if game.variant() == Variant::Practice {
            let pocketed = verdict
                .shot
                .as_ref()
                .map(|s| s.pocketed.as_slice())
                .unwrap_or(&[]);
            let scratched = pocketed.iter().any(|&(b, _)| b == 0);
            let potted = pocketed.iter().any(|&(b, _)| b != 0);
            let success = potted && !scratched;
            let value = match (success, scratched) {
                (true, _) => 1.0,
                (false, true) => 0.0,
                (false, false) => 0.3,
            };
            return Played { value, success };
        }
        Played {
            value: value::value(&g, self.me, sigma),
            success: verdict.succeeded_for(shooter),
        }
    }
}

impl Judge for GameJudge<'_> {
    async fn play(&mut self, strike: &Strike, call: Option<u8>, deep: bool) -> Played {
        let game = self.game;
        if !deep || game.variant() == Variant::Practice {
            return self.play_once(game, strike, call).await;
        }
        let Some((g, verdict)) = self.trial(game, self.me, strike, call).await else {
            return Played::REFUSED;
        };
        let keeps = verdict.over.is_none()
            && !verdict.foul
            && verdict.next == self.me
            && matches!(g.phase(), Phase::Shooting { in_hand: None, .. })
            && g.balls()
                .first()
                .is_some_and(|b| b.motion != MotionState::Pocketed);
        let success = verdict.succeeded_for(self.me);
        let value = if keeps {
            self.look_ahead(&g).await
        } else {
            value::value(&g, self.me, self.noise.aim_sigma())
        };
        Played { value, success }
    }

    fn meter(&self) -> &Meter {
        self.meter
    }

    fn look_ahead_guess(&self) -> usize {
        match self.game.variant() {
            // Practice has no look-ahead, and a carom table no pot to look ahead to.
            Variant::Practice | Variant::ThreeCushion { .. } => 0,
            _ => LOOK_AHEAD_GUESS,
        }
    }
}
