//! `breakshot-sim ai-study`: how well the computer player plays, and what it costs
//! (docs/computer-player.md). Every level plays the ghost-ball baseline and the level below
//! over whole games of 8-ball (both rule sets) and 9-ball; a fixed set of positions measures
//! strength against the search budget. Snooker has a study of its own (`snooker.rs`).

mod games;
mod plot;
pub mod snooker;

use std::fmt::Write as _;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use anyhow::Context;
use breakshot_shared::ai::{self, Level, Player, Rng};
use breakshot_shared::rules::{Command, EightBallRules, Game, Phase, Seat, Settings, Variant};

use games::{play, seated, Contestant, GameRecord};

/// The variants the games cycle through.
const VARIANTS: [Variant; 3] = [
    Variant::EightBall(EightBallRules::Wpa),
    Variant::NineBall,
    Variant::EightBall(EightBallRules::Bar),
];

/// Study size.
#[derive(Clone, Debug)]
pub struct Size {
    /// Games per pairing.
    pub games: usize,
    /// Positions for the budget curve.
    pub positions: usize,
    /// Worker threads.
    pub jobs: usize,
    /// The levels whose pairings are played (against the ghost-ball player and the level
    /// below).
    pub levels: Vec<u8>,
}

/// One pairing's games, seen from the first player ("us").
#[derive(Default)]
struct Match {
    games: usize,
    wins: usize,
    draws: usize,
    shots: u32,
    successes: u32,
    breaks: usize,
    break_and_runs: usize,
    times: Vec<f64>,
    sims: Vec<usize>,
}

impl Match {
    fn add(&mut self, r: &GameRecord, us: Seat) {
        let i = if us == Seat::A { 0 } else { 1 };
        self.games += 1;
        match r.winner {
            Some(w) if w == us => self.wins += 1,
            Some(_) => {}
            None => self.draws += 1,
        }
        self.shots += r.shots[i];
        self.successes += r.successes[i];
        if us == Seat::A {
            self.breaks += 1;
            self.break_and_runs += usize::from(r.break_and_run);
        }
        self.times.extend(&r.times[i]);
        self.sims.extend(&r.sims[i]);
    }

    fn win_rate(&self) -> f64 {
        (self.wins as f64 + 0.5 * self.draws as f64) / self.games.max(1) as f64
    }
}

pub(crate) fn quantile(v: &[f64], q: f64) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

/// Runs `count` jobs on `jobs` threads, collecting `f(k)` in order.
pub(crate) fn parallel<T: Send>(
    count: usize,
    jobs: usize,
    f: impl Fn(usize) -> T + Sync,
) -> Vec<T> {
    let next = AtomicUsize::new(0);
    let out: Mutex<Vec<(usize, T)>> = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..jobs.max(1) {
            s.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                if k >= count {
                    break;
                }
                let r = f(k);
                if let Ok(mut o) = out.lock() {
                    o.push((k, r));
                }
            });
        }
    });
    let mut v = out.into_inner().unwrap_or_default();
    v.sort_by_key(|(k, _)| *k);
    v.into_iter().map(|(_, t)| t).collect()
}

/// `games` games of `us` against `them`, seats and variants alternating.
fn pairing(us: Contestant, them: Contestant, games: usize, jobs: usize, salt: u64) -> Match {
    let records = parallel(games, jobs, |k| {
        let variant = VARIANTS[(k / 2) % VARIANTS.len()];
        seated(us, them, k, salt, |a, b, seed| play(variant, a, b, seed))
    });
    let mut m = Match::default();
    for (r, seat) in &records {
        m.add(r, *seat);
    }
    m
}

/// Every level of `size` against the ghost-ball player and, above level 1, against the level
/// below, as `(level, against the ghost, against the level below)`; `pairing(us, them, salt)`
/// plays one pairing. The progress lines start with `prefix` and call the ghost `ghost`.
fn level_pairings<T>(
    size: &Size,
    prefix: &str,
    ghost: &str,
    pairing: impl Fn(Contestant, Contestant, u64) -> T,
) -> Vec<(u8, T, Option<T>)> {
    let computer = |n| Contestant::Computer(Player::from(Level::new(n)));
    size.levels
        .iter()
        .map(|&n| {
            eprintln!("{prefix}level {n} against {ghost}…");
            let vs_ghost = pairing(computer(n), Contestant::Ghost, u64::from(n));
            let vs_below = (n > 1).then(|| {
                eprintln!("{prefix}level {n} against level {}…", n - 1);
                pairing(computer(n), computer(n - 1), 100 + u64::from(n))
            });
            (n, vs_ghost, vs_below)
        })
        .collect()
}

/// A report's title and the line that says how the study was run: `games` (how many, of
/// what), the threads and the time it took since `started`.
fn heading(title: &str, games: &str, size: &Size, started: Instant) -> String {
    format!(
        "# {title}\n\n{games}; {} threads; {:.0} s in all.\n\n",
        size.jobs,
        started.elapsed().as_secs_f64()
    )
}

/// A pairing's result as the reports show it: the share won, then the wins of those played.
fn won(rate: f64, wins: usize, played: usize) -> String {
    format!("{:.0}% ({wins}/{played})", 100.0 * rate)
}

/// Writes `text` into the file `name` in `out`.
fn write(out: &Path, name: &str, text: &str) -> anyhow::Result<()> {
    let path = out.join(name);
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))
}

/// Positions to shoot from: tables met in games between ghost-ball players, a shot due and
/// no ball in hand.
fn positions(count: usize) -> Vec<Game> {
    let mut out = Vec::new();
    let mut seed = 1;
    while out.len() < count && seed < 10_000 {
        let variant = VARIANTS[seed as usize % VARIANTS.len()];
        let mut game = Game::new(variant, Settings::offline(), seed);
        let mut ghost = Rng::new(seed);
        for n in 0..60 {
            let due =
                matches!(game.phase(), Phase::Shooting { in_hand: None, .. }) && !game.is_break();
            if due && n % 3 == 0 {
                out.push(game.clone());
                if out.len() >= count {
                    break;
                }
            }
            let Some(cmd) = ai::ghost_move(&game, &mut ghost) else {
                break;
            };
            if game.apply(game.to_move(), &cmd).is_err() {
                break;
            }
        }
        seed += 1;
    }
    out
}

/// One budget point: mean simulations per decision and the share of shots that succeeded.
struct BudgetPoint {
    label: String,
    sims: f64,
    success: f64,
    median_s: f64,
}

/// Trials of each decision under its own noise.
const EXECUTIONS: u64 = 6;

fn budget_point(label: &str, player: Player, positions: &[Game], jobs: usize) -> BudgetPoint {
    let rows = parallel(positions.len(), jobs, |k| {
        let game = &positions[k];
        let start = Instant::now();
        let cpu_start = games::cpu_seconds();
        let d = ai::plan(game, &player, k as u64 + 11);
        let t = match (cpu_start, games::cpu_seconds()) {
            (Some(a), Some(b)) => b - a,
            _ => start.elapsed().as_secs_f64(),
        };
        let Some(d) = d else {
            return (0, 0, 0, t);
        };
        let me = game.to_move();
        let mut ok = 0;
        for e in 0..EXECUTIONS {
            let mut g = game.clone();
            let cmd = ai::execute(d.command.clone(), player.noise, e * 31 + k as u64);
            let kept = match g.apply(me, &cmd) {
                Ok(v) => match &v.over {
                    Some((w, _)) => *w == Some(me),
                    None => matches!(cmd, Command::Shot { .. }) && !v.foul && v.next == me,
                },
                Err(_) => false,
            };
            ok += usize::from(kept);
        }
        (d.simulations, ok, EXECUTIONS as usize, t)
    });
    let n = rows.len().max(1) as f64;
    let sims = rows.iter().map(|r| r.0 as f64).sum::<f64>() / n;
    let ok: usize = rows.iter().map(|r| r.1).sum();
    let tries: usize = rows.iter().map(|r| r.2).sum();
    let times: Vec<f64> = rows.iter().map(|r| r.3).collect();
    BudgetPoint {
        label: label.to_string(),
        sims,
        success: ok as f64 / tries.max(1) as f64,
        median_s: quantile(&times, 0.5),
    }
}

/// The budget ladder: level 5's noise with searches from tiny to twice level 5's.
fn budgets() -> Vec<(String, Player)> {
    let top = Player::from(Level::new(5));
    let mut out = Vec::new();
    for n in 1..=5u8 {
        let mut p = Player::from(Level::new(n));
        p.noise = top.noise;
        out.push((format!("search of level {n}"), p));
    }
    let mut double = top;
    double.schedule.samples = top.schedule.samples.map(|s| 2 * s);
    double.schedule.keep = top.schedule.keep.map(|k| 2 * k);
    double.breadth.pots = 2 * top.breadth.pots;
    out.push(("twice level 5".into(), double));
    out
}

pub fn run(out: &Path, size: Size) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let started = Instant::now();
    let mut csv = String::from("pairing,level,games,wins,draws,win_rate,shots,shot_success,breaks,break_and_runs,median_decision_s,p95_decision_s,median_sims\n");
    let rows = level_pairings(&size, "", "the ghost-ball player", |us, them, salt| {
        pairing(us, them, size.games, size.jobs, salt)
    });
    let mut md = heading(
        "Computer player study",
        &format!("{} games per pairing (8-ball WPA, 9-ball and 8-ball bar rules in turn, breaks alternating)", size.games),
        &size,
        started,
    );
    let _ = writeln!(md, "| level | wins vs ghost-ball | wins vs level below | shot success | break-and-run | decision median | decision p95 | simulations (median) |");
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|");
    for (n, g, b) in &rows {
        let sims: Vec<f64> = g.sims.iter().map(|&s| s as f64).collect();
        let below = b.as_ref().map_or("—".to_string(), |b| {
            format!("{:.0}%", 100.0 * b.win_rate())
        });
        let _ = writeln!(
            md,
            "| {n} | {} | {below} | {:.0}% of {} | {:.0}% of {} | {:.3} s | {:.3} s | {:.0} |",
            won(g.win_rate(), g.wins, g.games),
            100.0 * g.successes as f64 / g.shots.max(1) as f64,
            g.shots,
            100.0 * g.break_and_runs as f64 / g.breaks.max(1) as f64,
            g.breaks,
            quantile(&g.times, 0.5),
            quantile(&g.times, 0.95),
            quantile(&sims, 0.5),
        );
        for (name, m) in [("ghost", Some(g)), ("below", b.as_ref())] {
            let Some(m) = m else { continue };
            let sims: Vec<f64> = m.sims.iter().map(|&s| s as f64).collect();
            let _ = writeln!(
                csv,
                "{name},{n},{},{},{},{:.4},{},{:.4},{},{},{:.4},{:.4},{:.0}",
                m.games,
                m.wins,
                m.draws,
                m.win_rate(),
                m.shots,
                m.successes as f64 / m.shots.max(1) as f64,
                m.breaks,
                m.break_and_runs,
                quantile(&m.times, 0.5),
                quantile(&m.times, 0.95),
                quantile(&sims, 0.5),
            );
        }
    }
    eprintln!("strength against the search budget…");
    let set = positions(size.positions);
    let points: Vec<BudgetPoint> = budgets()
        .into_iter()
        .map(|(label, p)| budget_point(&label, p, &set, size.jobs))
        .collect();
    let _ = writeln!(
        md,
        "\n## Strength against the search budget\n\n{} positions from ghost-ball games, level 5's execution noise, each decision executed {EXECUTIONS} times.\n",
        set.len()
    );
    let _ = writeln!(
        md,
        "| search | simulations per decision (mean) | shot success | decision median |"
    );
    let _ = writeln!(md, "|---|---|---|---|");
    let mut budget_csv = String::from("search,sims,success,median_decision_s\n");
    for p in &points {
        let _ = writeln!(
            md,
            "| {} | {:.0} | {:.1}% | {:.3} s |",
            p.label,
            p.sims,
            100.0 * p.success,
            p.median_s
        );
        let _ = writeln!(
            budget_csv,
            "{},{:.1},{:.4},{:.4}",
            p.label, p.sims, p.success, p.median_s
        );
    }
    write(out, "computer-player.md", &md)?;
    write(out, "computer-player.csv", &csv)?;
    write(out, "strength-budget.csv", &budget_csv)?;
    let png = out.join("strength-budget.png");
    plot::draw(
        &points
            .iter()
            .map(|p| (p.sims, p.success))
            .collect::<Vec<_>>(),
        &png,
    )
    .with_context(|| format!("drawing {}", png.display()))?;
    println!("{md}");
    Ok(())
}
