//! Practice: a sandbox with no turns and no fouls. Any ball can be placed anywhere free, a
//! whole layout can be loaded (for example from a scene file), and any shot can be played.

use glam::DVec2;

use crate::physics::{BallState, MotionState};
use crate::scene::Scene;

use super::facts::ShotFacts;
use super::{
    ball_name, capitalise, off_table, pocket_name, rack, Game, InHand, Next, RuleError, Ruling,
    Seat,
};

/// Practice layouts hold the cue ball and the fifteen object balls.
pub(super) const PRACTICE_BALLS: usize = 16;

pub(super) fn check_place_ball(
    game: &Game,
    ball: u8,
    pos: Option<[f64; 2]>,
) -> Result<(), RuleError> {
    let index = usize::from(ball);
    if index >= game.balls.len() {
        return Err(RuleError::IllegalPlacement(format!(
            "there is no ball {ball} (0 = cue ball, up to {})",
            game.balls.len() - 1
        )));
    }
    match pos {
        None => Ok(()),
        Some(p) if rack::is_free(&game.balls, index, DVec2::from_array(p), game.table()) => Ok(()),
        Some(_) => Err(RuleError::IllegalPlacement(format!(
            "{} must lie on the cloth, clear of the cushions, pockets and other balls",
            ball_name(ball)
        ))),
    }
}

pub(super) fn place_ball(game: &mut Game, ball: u8, pos: Option<[f64; 2]>) {
    if let Some(b) = game.balls.get_mut(usize::from(ball)) {
        *b = match pos {
            Some(p) => BallState::at_rest(DVec2::from_array(p)),
            None => off_table(),
        };
    }
}

pub(super) fn check_layout(game: &Game, layout: &[Option<[f64; 2]>]) -> Result<(), RuleError> {
    if layout.len() != game.balls.len() {
        return Err(RuleError::IllegalPlacement(format!(
            "a layout gives {} balls (0 = cue ball), not {}",
            game.balls.len(),
            layout.len()
        )));
    }
    let balls = layout_balls(layout);
    for (i, b) in balls.iter().enumerate() {
        if b.motion != MotionState::Pocketed && !rack::is_free(&balls, i, b.pos, game.table()) {
            return Err(RuleError::IllegalPlacement(format!(
                "{} must lie on the cloth, clear of the cushions, pockets and other balls",
                ball_name(i as u8)
            )));
        }
    }
    Ok(())
}

fn layout_balls(layout: &[Option<[f64; 2]>]) -> Vec<BallState> {
    layout
        .iter()
        .map(|p| match p {
            Some(p) => BallState::at_rest(DVec2::from_array(*p)),
            None => off_table(),
        })
        .collect()
}

pub(super) fn load_layout(game: &mut Game, layout: &[Option<[f64; 2]>]) {
    game.balls = layout_balls(layout);
    game.phase = super::Phase::Shooting {
        in_hand: Some(InHand::Anywhere),
        options: Vec::new(),
        push_out: false,
    };
}

/// The practice layout of a scene file: its balls must be named `cue` (or `0`) and `1` to
/// `15`; balls it does not name are off the table. Velocities, spins and the strike of the
/// scene are not part of a layout (shots are played with [`super::Command::Shot`]).
pub fn layout_from_scene(scene: &Scene) -> Result<Vec<Option<[f64; 2]>>, RuleError> {
    let mut layout = vec![None; PRACTICE_BALLS];
    for b in &scene.balls {
        let number = match b.id.as_str() {
            "cue" => Some(0),
            id => id.parse::<usize>().ok().filter(|&n| n < PRACTICE_BALLS),
        };
        let Some(n) = number else {
            return Err(RuleError::IllegalPlacement(format!(
                "scene ball \"{}\" is not a pool ball (use \"cue\" and \"1\" to \"15\")",
                b.id
            )));
        };
        if layout[n].is_some() {
            return Err(RuleError::IllegalPlacement(format!(
                "scene names {} twice",
                ball_name(n as u8)
            )));
        }
        layout[n] = Some(b.pos);
    }
    Ok(layout)
}

/// A practice shot is never a foul: report what fell, and play on (the cue ball stays in
/// hand, as it always is in practice).
pub(super) fn judge(game: &mut Game, shooter: Seat, facts: &ShotFacts) -> Ruling {
    let reasons = facts
        .pocketed
        .iter()
        .map(|&(b, p)| {
            format!(
                "{} fell in the {}",
                capitalise(&ball_name(b)),
                pocket_name(game.table(), p)
            )
        })
        .collect();
    Ruling {
        reasons,
        foul: false,
        next: Next::Shoot {
            seat: shooter,
            in_hand: Some(InHand::Anywhere),
            options: Vec::new(),
        },
    }
}
