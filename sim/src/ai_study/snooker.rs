//! `breakshot-sim ai-study --snooker REDS`: the computer player at snooker. Every level plays
//! frames against the simple potter (the ghost-ball player, which aims a pot at a ball on
//! and never plays safe) and against the level below; the study counts frames won, the
//! breaks made (their mean, the highest, those of 20 or more), fouls and points per frame.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use breakshot_shared::rules::{Game, Seat, Settings, Variant};

use super::games::{seated, Contestant, Seats};
use super::{heading, level_pairings, parallel, quantile, won, write, Size};

/// A frame stops undecided after this many commands (keeps the study bounded).
const MAX_COMMANDS: usize = 800;
/// A break of this many points or more is counted on its own.
const BIG_BREAK: u32 = 20;

/// One frame, per seat (index 0 = A, who breaks off).
#[derive(Clone, Debug, Default)]
struct Frame {
    winner: Option<Seat>,
    scores: [u32; 2],
    /// Every break of at least one point, as it ended.
    breaks: [Vec<u32>; 2],
    fouls: [u32; 2],
    strokes: [u32; 2],
    /// Decision times (s) of each seat's strokes and placements.
    times: [Vec<f64>; 2],
}

/// Plays one frame of `reds` reds from `seed`: `a` in seat A, `b` in seat B.
fn play(reds: u8, a: Contestant, b: Contestant, seed: u64) -> Frame {
    let variant = Variant::Snooker { reds, best_of: 1 };
    let mut game = Game::new(variant, Settings::offline(), seed);
    let mut seats = Seats::new(a, b, seed);
    let mut f = Frame::default();
    for n in 0..MAX_COMMANDS {
        let Some((seat, chosen)) = seats.choose(&game, n) else {
            break;
        };
        let i = seat.index();
        let is_shot = chosen.is_shot();
        let before = game.snooker().map_or(0, |m| m.break_points);
        let verdict = match game.apply(seat, &chosen.command) {
            Ok(v) => v,
            // A refused command would be a bug in a player: the other seat wins.
            Err(_) => {
                f.winner = Some(seat.other());
                break;
            }
        };
        let Some(m) = game.snooker() else { break };
        f.scores = m.scores;
        if is_shot {
            f.strokes[i] += 1;
            f.fouls[i] += u32::from(verdict.foul);
            let kept = verdict.over.is_none() && !verdict.foul && verdict.next == seat;
            if !kept {
                let ended = if verdict.foul {
                    before
                } else {
                    before.max(m.break_points)
                };
                if ended > 0 {
                    f.breaks[i].push(ended);
                }
            }
        }
        if let Some((winner, _)) = verdict.over {
            f.winner = winner;
            break;
        }
    }
    f.times = seats.times;
    f
}

/// One pairing's frames, seen from the first player ("us").
#[derive(Default)]
struct Tally {
    frames: usize,
    wins: usize,
    undecided: usize,
    breaks: Vec<u32>,
    fouls: u32,
    strokes: u32,
    points: u64,
    times: Vec<f64>,
}

impl Tally {
    fn add(&mut self, f: &Frame, us: Seat) {
        let i = us.index();
        self.frames += 1;
        match f.winner {
            Some(w) if w == us => self.wins += 1,
            Some(_) => {}
            None => self.undecided += 1,
        }
        self.breaks.extend(&f.breaks[i]);
        self.fouls += f.fouls[i];
        self.strokes += f.strokes[i];
        self.points += u64::from(f.scores[i]);
        self.times.extend(&f.times[i]);
    }

    fn win_rate(&self) -> f64 {
        (self.wins as f64 + 0.5 * self.undecided as f64) / self.frames.max(1) as f64
    }

    fn mean_break(&self) -> f64 {
        self.breaks.iter().map(|&b| f64::from(b)).sum::<f64>() / self.breaks.len().max(1) as f64
    }

    fn per_frame(&self, x: f64) -> f64 {
        x / self.frames.max(1) as f64
    }
}

/// `frames` frames of `us` against `them`, seats alternating.
fn pairing(reds: u8, us: Contestant, them: Contestant, size: &Size, salt: u64) -> Tally {
    let frames = parallel(size.games, size.jobs, |k| {
        seated(us, them, k, salt, |a, b, seed| play(reds, a, b, seed))
    });
    let mut t = Tally::default();
    for (f, seat) in &frames {
        t.add(f, *seat);
    }
    t
}

/// Runs the snooker study and writes `snooker.md` and `snooker.csv` into `out`.
pub fn run(out: &Path, reds: u8, size: &Size) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let started = Instant::now();
    let rows = level_pairings(size, "snooker: ", "the simple potter", |us, them, salt| {
        pairing(reds, us, them, size, salt)
    });
    let mut md = heading(
        "Computer player study: snooker",
        &format!("{} frames of {reds} reds per pairing (seats alternating, seat A breaks off); the simple potter is the ghost-ball player", size.games),
        size,
        started,
    );
    let _ = writeln!(md, "| level | frames won vs simple potter | vs level below | mean break | highest break | breaks of {BIG_BREAK}+ | points per frame | fouls per frame | decision median |");
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|");
    let mut csv = String::from("pairing,level,frames,wins,undecided,win_rate,breaks,mean_break,highest_break,big_breaks,points_per_frame,fouls_per_frame,strokes,median_decision_s\n");
    for (n, p, b) in &rows {
        let below = b
            .as_ref()
            .map_or("—".to_string(), |b| won(b.win_rate(), b.wins, b.frames));
        let _ = writeln!(
            md,
            "| {n} | {} | {below} | {:.1} | {} | {} | {:.1} | {:.1} | {:.3} s |",
            won(p.win_rate(), p.wins, p.frames),
            p.mean_break(),
            p.breaks.iter().max().copied().unwrap_or(0),
            p.breaks.iter().filter(|&&x| x >= BIG_BREAK).count(),
            p.per_frame(p.points as f64),
            p.per_frame(f64::from(p.fouls)),
            quantile(&p.times, 0.5),
        );
        for (name, t) in [("potter", Some(p)), ("below", b.as_ref())] {
            let Some(t) = t else { continue };
            let _ = writeln!(
                csv,
                "{name},{n},{},{},{},{:.4},{},{:.3},{},{},{:.2},{:.2},{},{:.4}",
                t.frames,
                t.wins,
                t.undecided,
                t.win_rate(),
                t.breaks.len(),
                t.mean_break(),
                t.breaks.iter().max().copied().unwrap_or(0),
                t.breaks.iter().filter(|&&x| x >= BIG_BREAK).count(),
                t.per_frame(t.points as f64),
                t.per_frame(f64::from(t.fouls)),
                t.strokes,
                quantile(&t.times, 0.5),
            );
        }
    }
    write(out, "snooker.md", &md)?;
    write(out, "snooker.csv", &csv)?;
    println!("{md}");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_between_two_potters_ends_and_its_breaks_add_up_to_no_more_than_the_scores() {
        let f = play(6, Contestant::Ghost, Contestant::Ghost, 3);
        assert!(f.winner.is_some(), "{f:?}");
        for i in 0..2 {
            let made: u32 = f.breaks[i].iter().sum();
            // The rest of a score is the other player's fouls.
            assert!(made <= f.scores[i], "{f:?}");
        }
        assert!(f.strokes.iter().sum::<u32>() > 0);
    }
}
