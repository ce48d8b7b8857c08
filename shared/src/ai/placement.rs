//! Ball in hand: where to put the cue ball, by search.
//!
//! Spots are proposed behind every pottable ball on its line to each pocket (a straight or
//! gently cut pot at a comfortable distance) and on a coarse grid over the allowed area; the
//! most promising by geometry are each searched as a shot, and the spot whose best shot is
//! worth most wins. The search is seeded from the object balls alone, so that asking again
//! once the cue ball is on the chosen spot gives the same spot, and the player shoots.

use glam::DVec2;

use super::candidates::View;
use super::game_judge::GameJudge;
use super::geometry::{rotate, Layout};
use super::lab::Lab;
use super::noise::mix;
use super::thinking::Meter;
use super::{candidates, search, value, Player};
use crate::physics::{BallState, Strike};
use crate::rules::{rack, Command, Game, InHand};

/// The best spot for the cue ball.
pub(super) async fn best_spot(
    game: &Game,
    player: &Player,
    area: Option<InHand>,
    meter: &Meter,
) -> Option<[f64; 2]> {
    let me = game.to_move();
    let layout = Layout::new(game.table(), game.balls());
    let pottable = value::pottable(game);
    let sigma = player.noise.aim_sigma();
    let r = layout.radius;
    let head = rack::head_string(game.table());
    let mut spots: Vec<DVec2> = Vec::new();
    if game.is_break() {
        spots.push(rack::break_spot(game.table()));
    }
    for &(ball, ob) in layout.balls.iter().filter(|(b, _)| *b != 0) {
        if !pottable.is_empty() && !pottable.contains(&ball) {
            continue;
        }
        for pocket in &layout.pockets {
            let toward = (pocket.center - ob).normalize_or_zero();
            let ghost = ob - toward * (2.0 * r);
            for dist in [0.25, 0.5] {
                for turn in [0.0f64, 0.35, -0.35] {
                    spots.push(ghost - rotate(toward, turn) * dist);
                }
            }
        }
    }
    let (w, l) = (layout.size.x, layout.size.y);
    let top = if area == Some(InHand::Kitchen) {
        head
    } else {
        l
    };
    for i in 0..5 {
        for j in 0..8 {
            spots.push(DVec2::new(
                w * (i as f64 + 0.5) / 5.0,
                top * (j as f64 + 0.5) / 8.0,
            ));
        }
    }
    let mut ranked: Vec<(f64, [f64; 2], usize)> = spots
        .iter()
        .enumerate()
        .map(|(k, p)| (k, p.to_array()))
        .filter(|(_, p)| game.legal_cue_placement(*p).is_ok())
        .map(|(k, p)| {
            let q = layout.best_pot(DVec2::from_array(p), &pottable, sigma);
            (q, p, k)
        })
        .collect();
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.2.cmp(&b.2)));
    if ranked.is_empty() {
        return None;
    }
    // Seeded by the object balls only: the cue ball's own position must not matter.
    let objects: Vec<BallState> = game.balls().iter().skip(1).copied().collect();
    let seed = crate::hash::state_hash(&objects);
    let mut best: Option<(f64, [f64; 2])> = None;
    let searched = player.placements.max(1).min(ranked.len());
    let mut breadth = player.breadth;
    breadth.pots = breadth.pots.min(4);
    breadth.banks = false;
    breadth.kicks = false;
    let schedule = search::Schedule {
        samples: [2, 6, player.schedule.samples[1]],
        keep: [6, 2],
        look_ahead: false,
    };
    let per_spot = super::estimate::shot(&breadth, &schedule, 0);
    for (k, &(_, spot, _)) in ranked.iter().take(searched).enumerate() {
        meter.expect_afterwards(per_spot * (searched - k - 1));
        let mut g = game.clone();
        if g.apply(me, &Command::PlaceCueBall { pos: spot }).is_err() {
            continue;
        }
        let layout = Layout::new(g.table(), g.balls());
        let targets = g.legal_first_balls();
        let view = View {
            layout: &layout,
            targets: &targets,
            pottable: &pottable,
            aim_sigma: sigma,
        };
        let probe = Strike {
            speed: 1.0,
            dir: DVec2::Y,
            tip: DVec2::ZERO,
            elevation_deg: 0.0,
        };
        meter.expect(per_spot);
        let mut lab = Lab::new(g.shot_for(&probe), meter);
        let cands = candidates::generate(&mut lab, &view, &breadth).await;
        let mut judge = GameJudge::new(&g, player, meter);
        let choice = search::choose(
            &mut judge,
            &cands,
            player.noise,
            &schedule,
            mix(seed, 0x91A),
        )
        .await;
        let v = choice.map_or(0.0, |c| c.value);
        if best.is_none_or(|(bv, _)| v > bv) {
            best = Some((v, spot));
        }
    }
    meter.expect_afterwards(0);
    best.map(|(_, s)| s).or(Some(ranked[0].1))
}
