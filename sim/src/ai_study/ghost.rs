//! The ghost-ball player of `breakshot-bot`, written out again as a baseline opponent: aim at
//! a legal ball's ghost position for a pocket (one of the three straightest, at random), a
//! little aim noise, a random speed and follow/draw; break at full pace; accept the table
//! when offered; put the cue ball anywhere legal when it is off the table.

use breakshot_shared::ai::Rng;
use breakshot_shared::ai::{ranked_pots, GhostView};
use breakshot_shared::physics::{BallState, MotionState, Params, Strike};
use breakshot_shared::rules::{Choice, Command, Game, InHand, Phase};
use glam::DVec2;

pub struct Ghost {
    rng: Rng,
}

impl Ghost {
    pub fn new(seed: u64) -> Ghost {
        Ghost {
            rng: Rng::new(seed),
        }
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.rng.unit()
    }

    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.rng.next_u64() % n as u64) as usize
        }
    }

    pub fn choose(&mut self, game: &Game) -> Option<Command> {
        match game.phase() {
            Phase::Deciding { options } => {
                let choice = if options.contains(&Choice::AcceptTable) {
                    Choice::AcceptTable
                } else {
                    *options.first()?
                };
                Some(Command::Decide(choice))
            }
            Phase::Shooting {
                in_hand: Some(area),
                ..
            } if off_table(&game.balls()[0]) => Some(Command::PlaceCueBall {
                pos: self.placement(game, *area)?,
            }),
            Phase::Shooting { .. } => {
                let (strike, call) = self.aim(game);
                Some(Command::Shot { strike, call })
            }
            Phase::Over { .. } => None,
        }
    }

    fn placement(&mut self, game: &Game, area: InHand) -> Option<[f64; 2]> {
        let (w, l) = game.table().size()?;
        let r = Params::default().ball_radius;
        let max_y = match area {
            InHand::Kitchen => l / 4.0 - r,
            InHand::Anywhere => l - 2.0 * r,
        };
        (0..200)
            .map(|_| [self.range(2.0 * r, w - 2.0 * r), self.range(2.0 * r, max_y)])
            .find(|p| game.legal_cue_placement(*p).is_ok())
    }

    fn aim(&mut self, game: &Game) -> (Strike, Option<u8>) {
        let r = game.params().ball_radius;
        let GhostView {
            cue,
            targets,
            pockets,
        } = GhostView::of(game);
        if game.is_break() || targets.is_empty() {
            let at = targets
                .iter()
                .map(|t| t.1)
                .min_by(|a, b| a.distance(cue).total_cmp(&b.distance(cue)))
                .unwrap_or(cue + DVec2::Y);
            let a = self.range(-0.01, 0.01);
            let dir = rotate((at - cue).normalize_or(DVec2::Y), a);
            let strike = Strike {
                speed: self.range(8.0, 10.0),
                dir,
                tip: DVec2::ZERO,
                elevation_deg: 0.0,
            };
            return (strike, None);
        }
        let options = ranked_pots(cue, &targets, &pockets, r);
        let k = self.below(options.len().min(3));
        let (aim, call) = match options.get(k).copied() {
            Some((_, aim, pocket)) => (aim, Some(pocket)),
            None => {
                let (_, t) = targets[self.below(targets.len())];
                let nearest = (0..pockets.len())
                    .min_by(|a, b| pockets[*a].distance(t).total_cmp(&pockets[*b].distance(t)))
                    .map(|k| k as u8);
                ((t - cue).normalize_or(DVec2::Y), nearest)
            }
        };
        let a = self.range(-0.008, 0.008);
        let strike = Strike {
            speed: self.range(2.5, 5.0),
            dir: rotate(aim, a),
            tip: DVec2::new(0.0, self.range(-0.2, 0.3)),
            elevation_deg: 0.0,
        };
        (strike, call)
    }
}

fn off_table(b: &BallState) -> bool {
    b.pocket.is_some() || b.motion == MotionState::Pocketed
}

fn rotate(v: DVec2, angle: f64) -> DVec2 {
    let (s, c) = angle.sin_cos();
    DVec2::new(v.x * c - v.y * s, v.x * s + v.y * c)
}
