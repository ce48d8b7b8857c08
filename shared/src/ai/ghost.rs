//! The ghost-ball player, by geometry alone: the baseline player of the load bot and of the
//! computer player's study. It aims at a legal ball's ghost position for a pocket (one of the
//! three straightest pots, at random) with a little aim noise, a random speed and follow or
//! draw; breaks at full pace; accepts the table when offered; and puts a cue ball in hand
//! anywhere legal when it may not be shot from where it lies.

use glam::DVec2;

use super::geometry::rotate;
use super::noise::Rng;
use crate::physics::{Strike, Table};
use crate::rules::{is_off_table, Choice, Command, Game, InHand, Phase};

/// The ghost-ball player's move for the seat to move, its randomness drawn from `rng`;
/// `None` when the game is over (or no legal spot for a ball in hand was found).
pub fn ghost_move(game: &Game, rng: &mut Rng) -> Option<Command> {
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
        } if must_place(game) => Some(Command::PlaceCueBall {
            pos: placement(game, *area, rng)?,
        }),
        Phase::Shooting { .. } => {
            let (strike, pocket) = aim(game, rng);
            // Name the pocket aimed at when the rules ask for a call.
            let call = pocket.filter(|_| game.needs_call());
            Some(Command::Shot { strike, call })
        }
        Phase::Over { .. } => None,
    }
}

/// With the cue ball in hand: must it be placed before the shot? It must when it is off the
/// table, and when the rules would refuse a shot from where it lies (against a cushion or
/// another ball, or outside the kitchen).
fn must_place(game: &Game) -> bool {
    let cue = &game.balls()[game.cue_ball()];
    is_off_table(cue) || game.legal_cue_placement(cue.pos.to_array()).is_err()
}

/// A random legal spot in `area`: two radii clear of the cushions, and a radius short of
/// the head string in the kitchen.
fn placement(game: &Game, area: InHand, rng: &mut Rng) -> Option<[f64; 2]> {
    let (lo, hi) = game.in_hand_area(area);
    let r = game.params().ball_radius;
    let max_y = match area {
        InHand::Kitchen | InHand::D => hi.y - r,
        InHand::Anywhere => hi.y - 2.0 * r,
    };
    (0..200)
        .map(|_| {
            [
                rng.range(lo.x + 2.0 * r, hi.x - 2.0 * r),
                rng.range(lo.y + 2.0 * r, max_y),
            ]
        })
        .find(|p| game.legal_cue_placement(*p).is_ok())
}

/// Ghost-ball aim at a legal ball into a pocket, with a little noise; the break (or a table
/// with nothing to aim at) is a hard hit at the nearest ball. Returns the pocket aimed at.
fn aim(game: &Game, rng: &mut Rng) -> (Strike, Option<u8>) {
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
        let dir = rotate((at - cue).normalize_or(DVec2::Y), rng.range(-0.01, 0.01));
        let strike = Strike {
            speed: rng.range(8.0, 10.0),
            dir,
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        };
        return (strike, None);
    }
    let options = ranked_pots(cue, &targets, &pockets, r);
    let (aim, call) = match options.get(below(rng, options.len().min(3))).copied() {
        Some((_, aim, pocket)) => (aim, Some(pocket)),
        None => {
            let (_, t) = targets[below(rng, targets.len())];
            let nearest = (0..pockets.len())
                .min_by(|a, b| pockets[*a].distance(t).total_cmp(&pockets[*b].distance(t)))
                .map(|k| k as u8);
            ((t - cue).normalize_or(DVec2::Y), nearest)
        }
    };
    // Drawn in this order (aim, speed, tip): the study's recorded games depend on it.
    let dir = rotate(aim, rng.range(-0.008, 0.008));
    let strike = Strike {
        speed: rng.range(2.5, 5.0),
        dir,
        tip: DVec2::new(0.0, rng.range(-0.2, 0.3)),
        elevation_deg: 0.0,
    };
    (strike, call)
}

/// A number in `0..n`, drawing nothing when `n` is 0.
fn below(rng: &mut Rng, n: usize) -> usize {
    if n == 0 {
        0
    } else {
        (rng.next_u64() % n as u64) as usize
    }
}

/// What the ghost-ball player looks at in a game: the cue ball, the balls it may aim at
/// (those the rules let it hit first, still on the table) and the pockets' centres.
struct GhostView {
    /// The cue ball's centre.
    pub cue: DVec2,
    /// The balls that may be aimed at, with their centres.
    pub targets: Vec<(u8, DVec2)>,
    /// The pockets' centres.
    pub pockets: Vec<DVec2>,
}

impl GhostView {
    /// The view of `game` as it stands.
    fn of(game: &Game) -> GhostView {
        let balls = game.balls();
        let table = Table::new(game.table());
        let legal = game.legal_first_balls();
        GhostView {
            cue: balls[game.cue_ball()].pos,
            targets: balls
                .iter()
                .enumerate()
                .filter(|&(i, b)| i != game.cue_ball() && !is_off_table(b))
                .filter(|&(i, _)| legal.is_empty() || legal.contains(&(i as u8)))
                .map(|(i, b)| (i as u8, b.pos))
                .collect(),
            pockets: table
                .pockets
                .iter()
                .map(|p| table.to_scene(p.center))
                .collect(),
        }
    }
}

/// Every pot of a target into a pocket that the ghost-ball aim makes at all likely (the cue
/// ball's aim within about 73° of the object ball's path), best first: `(score, aim,
/// pocket)`, scored by straightness less a tenth of the distance the balls travel.
fn ranked_pots(
    cue: DVec2,
    targets: &[(u8, DVec2)],
    pockets: &[DVec2],
    radius: f64,
) -> Vec<(f64, DVec2, u8)> {
    let mut options = Vec::new();
    for (_, t) in targets {
        for (k, p) in pockets.iter().enumerate() {
            let to_pocket = (*p - *t).normalize_or_zero();
            let ghost = *t - to_pocket * (2.0 * radius);
            let aim = (ghost - cue).normalize_or_zero();
            let straightness = aim.dot(to_pocket);
            if straightness > 0.3 {
                let dist = ghost.distance(cue) + p.distance(*t);
                options.push((straightness - 0.1 * dist, aim, k as u8));
            }
        }
    }
    options.sort_by(|a, b| b.0.total_cmp(&a.0));
    options
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rules::{rack, Seat, Settings, Variant};

    /// A practice game with the cue ball (`None`: off the table) and balls 1, 2… at the
    /// spots.
    fn practice(cue: Option<[f64; 2]>, others: &[[f64; 2]]) -> Game {
        let mut game = Game::new(Variant::Practice, Settings::offline(), 1);
        let mut balls = vec![None; 16];
        balls[0] = cue;
        for (b, p) in balls[1..].iter_mut().zip(others) {
            *b = Some(*p);
        }
        game.apply(game.to_move(), &Command::LoadLayout { balls })
            .expect("layout accepted");
        game
    }

    #[test]
    fn breaks_hard_at_the_nearest_ball() {
        let game = Game::new(Variant::NineBall, Settings::offline(), 3);
        let to_apex = game.balls()[1].pos - game.balls()[0].pos;
        for seed in 0..20 {
            let shot = ghost_move(&game, &mut Rng::new(seed));
            let Some(Command::Shot { strike, call: None }) = shot else {
                panic!("{shot:?}");
            };
            assert!((8.0..10.0).contains(&strike.speed), "{strike:?}");
            assert!(strike.dir.angle_to(to_apex).abs() <= 0.01, "{strike:?}");
        }
    }

    #[test]
    fn aims_at_the_ghost_ball_of_one_of_the_three_straightest_pots() {
        // Ball 1 straight in line with the top-left corner (pocket 2), the cue ball behind;
        // ball 2 a cut into the top-right corner, ball 3 into the bottom left: five pots in
        // all, of which the three best are tried.
        let game = practice(Some([0.6, 1.94]), &[[0.3, 2.24], [0.9, 2.3], [0.3, 1.4]]);
        let view = GhostView::of(&game);
        let ranked = ranked_pots(view.cue, &view.targets, &view.pockets, 0.028575);
        let top: Vec<u8> = ranked.iter().take(3).map(|o| o.2).collect();
        assert_eq!(top[0], 2);
        let mut seen = Vec::new();
        for seed in 0..40 {
            let (strike, pocket) = aim(&game, &mut Rng::new(seed));
            let pocket = pocket.expect("a pot");
            assert!(top.contains(&pocket), "{pocket} not in {top:?}");
            let ghost_aim = ranked.iter().find(|o| o.2 == pocket).expect("ranked").1;
            assert!(strike.dir.angle_to(ghost_aim).abs() <= 0.008, "{strike:?}");
            assert!((2.5..5.0).contains(&strike.speed));
            assert!(strike.tip.x == 0.0 && (-0.2..0.3).contains(&strike.tip.y));
            seen.push(pocket);
            // The straight pot is aimed well enough to go in.
            if pocket == 2 {
                let mut g = game.clone();
                let shot = Command::Shot { strike, call: None };
                let pocketed = g.apply(g.to_move(), &shot).unwrap().shot.unwrap().pocketed;
                assert!(pocketed.contains(&(1, 2)), "seed {seed}: {pocketed:?}");
            }
        }
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), 3, "each of the three is chosen: {seen:?}");
    }

    #[test]
    fn places_a_cue_ball_in_hand_legally_in_its_area() {
        let game = practice(None, &[[0.6, 1.5]]);
        let mut rng = Rng::new(4);
        let placed = ghost_move(&game, &mut rng);
        let Some(Command::PlaceCueBall { pos }) = placed else {
            panic!("{placed:?}");
        };
        assert!(game.legal_cue_placement(pos).is_ok());
        let mut spots: Vec<_> = (0..20)
            .map(|_| placement(&game, InHand::Kitchen, &mut rng).expect("a spot"))
            .collect();
        for p in &spots {
            let head = rack::head_string(game.table());
            assert!(p[1] < head && game.legal_cue_placement(*p).is_ok(), "{p:?}");
        }
        spots.dedup();
        assert_eq!(spots.len(), 20, "spots are drawn at random");
    }

    #[test]
    fn places_a_cue_ball_in_hand_the_rules_would_not_let_it_shoot_from_where_it_lies() {
        // A game of the cluster study in which a foul leaves the cue ball in hand against
        // the top cushion: shot from there, the rules would refuse it.
        let seed = 1_001_177;
        let mut game = Game::new(Variant::NineBall, Settings::offline(), seed);
        let mut players = [Rng::new(seed ^ 0xA), Rng::new(seed ^ 0xB)];
        let mut met = false;
        for _ in 0..80 {
            let in_hand = matches!(
                game.phase(),
                Phase::Shooting {
                    in_hand: Some(_),
                    ..
                }
            );
            met |= in_hand && must_place(&game) && !is_off_table(&game.balls()[0]);
            let seat = game.to_move();
            let rng = &mut players[usize::from(seat == Seat::B)];
            let Some(command) = ghost_move(&game, rng) else {
                break;
            };
            let verdict = game.apply(seat, &command);
            assert!(verdict.is_ok(), "{command:?}: {verdict:?}");
        }
        assert!(met, "the game no longer leaves such a spot");
    }
}
