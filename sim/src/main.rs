//! `breakshot-sim`: simulate scene files (docs/scene.md) from the command line.

mod ai_study;
mod chart;
mod cluster_study;
mod fit;
mod study;
mod suggest;

use std::io::Read;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use breakshot_shared::physics::Simulator;
use breakshot_shared::scene::Scene;
use breakshot_shared::scene_code;
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "breakshot-sim", version, about = "Simulate Breakshot scenes")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene and print the result as JSON.
    Run {
        /// Scene file, - for standard input, or a position code (`bs1.…`).
        scene: String,
        /// Also print every ball's state every DT seconds.
        #[arg(long, value_name = "DT")]
        sample: Option<f64>,
    },
    /// Time the simulation of a scene and print the timing as JSON.
    Bench {
        /// Scene file, - for standard input, or a position code (`bs1.…`).
        scene: String,
        /// How many timed runs.
        #[arg(long, default_value_t = 1000)]
        runs: usize,
    },
    /// Measure what accuracy costs: the event-based engine against fixed-step integration,
    /// and the cost of each effect (docs/accuracy-cost.md).
    AccuracyCost {
        /// Folder for accuracy-cost.md, accuracy-cost.csv and accuracy-cost.png.
        #[arg(long, value_name = "DIR", default_value = "out/accuracy-cost")]
        out: PathBuf,
    },
    /// Play random games and report events per shot as JSON (docs/stability.md).
    ClusterStudy {
        /// How many games.
        #[arg(long, default_value_t = 1000)]
        games: usize,
        /// Most strikes per game, the break included.
        #[arg(long, default_value_t = 10)]
        shots: usize,
        /// Seed of the games.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Fit cue strikes (and the shared cloth and cushion parameters) to recorded shots and
    /// report how close the simulation comes (docs/reality.md).
    Fit(fit::cli::Args),
    /// Print the position of a scene (its table and balls) as a short code; every command
    /// that takes a scene file also takes such a code in its place.
    Code {
        /// Scene file, - for standard input, or a code (printed as a scene file).
        scene: String,
    },
    /// Suggest a strike for the cue ball that hits and pockets one of the targets.
    Suggest {
        /// Scene file, - for standard input, or a position code (`bs1.…`).
        scene: String,
        /// Ids of the balls that may be hit first and pocketed, comma-separated.
        #[arg(long, value_name = "ID[,ID...]")]
        targets: String,
        /// Playing strength, 1 to 5.
        #[arg(long, default_value_t = 5)]
        level: u8,
        /// Seed of the search's noise.
        #[arg(long, default_value_t = 0)]
        seed: u64,
    },
    /// Measure the computer player: win rates, shot success, decision time, budget
    /// (docs/computer-player.md).
    AiStudy {
        /// Folder for computer-player.md, the CSV files and strength-budget.png.
        #[arg(long, value_name = "DIR", default_value = "out/ai-study")]
        out: PathBuf,
        /// Games per pairing.
        #[arg(long, default_value_t = 60)]
        games: usize,
        /// Positions for the budget curve.
        #[arg(long, default_value_t = 60)]
        positions: usize,
        /// Worker threads.
        #[arg(long, default_value_t = 1)]
        jobs: usize,
        /// Levels to pair (each against the ghost-ball player and the level below).
        #[arg(long, value_delimiter = ',', default_values_t = [1u8, 2, 3, 4, 5])]
        levels: Vec<u8>,
        /// Study snooker instead, frames of REDS reds (6, 10 or 15): frames won against the
        /// simple potter and the level below, the breaks made (snooker.md, snooker.csv).
        #[arg(long, value_name = "REDS", value_parser = ["6", "10", "15"])]
        snooker: Option<String>,
    },
}

/// Exit code for a scene or argument that is not valid (the contract's).
const INVALID: u8 = 2;

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Invalid(msg)) => {
            eprintln!("{msg}");
            ExitCode::from(INVALID)
        }
        Err(Failure::Other(e)) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

enum Failure {
    Invalid(String),
    Other(anyhow::Error),
}

impl From<anyhow::Error> for Failure {
    fn from(e: anyhow::Error) -> Self {
        Failure::Other(e)
    }
}

/// The scene at `path` (a file, or - for standard input), or the position a code given in
/// its place stands for (`bs1.…`, as the game shares them).
fn load(path: &str) -> Result<Scene, Failure> {
    if path.starts_with(scene_code::PREFIX) {
        return scene_code::decode(path).map_err(|e| Failure::Invalid(e.to_string()));
    }
    let mut text = String::new();
    if path == "-" {
        std::io::stdin()
            .read_to_string(&mut text)
            .context("reading the scene from standard input")?;
    } else {
        text = std::fs::read_to_string(path).with_context(|| format!("reading {path}"))?;
    }
    Scene::from_json(&text).map_err(|e| Failure::Invalid(one_line(&e.to_string())))
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn run(command: Command) -> Result<(), Failure> {
    match command {
        Command::Run { scene, sample } => {
            let scene = load(&scene)?;
            let result = scene
                .run(sample)
                .map_err(|e| Failure::Invalid(one_line(&e.to_string())))?;
            println!(
                "{}",
                serde_json::to_string_pretty(&result).context("encoding")?
            );
        }
        Command::Bench { scene, runs } => {
            if runs == 0 {
                return Err(Failure::Invalid("--runs must be at least 1".into()));
            }
            let scene = load(&scene)?;
            let shot = scene
                .to_shot()
                .map_err(|e| Failure::Invalid(one_line(&e.to_string())))?;
            let mut sim = Simulator::new();
            let events = sim
                .run(&shot)
                .map_err(|e| Failure::Invalid(one_line(&scene.explain(e).to_string())))?
                .events
                .len();
            // Warm-up: caches, branch predictors and the simulator's buffers.
            let warmup = (runs / 10).clamp(1, 100);
            for _ in 0..warmup {
                let _ = sim.run(&shot);
            }
            let mut times = Vec::with_capacity(runs);
            for _ in 0..runs {
                let start = Instant::now();
                let out = sim.run(&shot);
                let elapsed = start.elapsed();
                std::hint::black_box(&out);
                times.push(elapsed.as_secs_f64() * 1e6);
            }
            times.sort_by(f64::total_cmp);
            let pick = |q: f64| times[((times.len() - 1) as f64 * q).round() as usize];
            let report = serde_json::json!({
                "runs": runs,
                "events": events,
                "median_us": pick(0.5),
                "min_us": times[0],
                "p90_us": pick(0.9),
            });
            println!("{report}");
        }
        Command::AccuracyCost { out } => study::run(&out)?,
        Command::ClusterStudy { games, shots, seed } => {
            let summary = cluster_study::run(games, shots, seed);
            println!("{}", serde_json::to_string(&summary).context("encoding")?);
        }
        Command::Fit(args) => fit::cli::run(args).map_err(|e| match e {
            fit::cli::Error::Invalid(msg) => Failure::Invalid(msg),
            fit::cli::Error::Other(e) => Failure::Other(e),
        })?,
        Command::Code { scene } => {
            // A code is printed back as the scene it stands for, a scene file as its code.
            let loaded = load(&scene)?;
            if scene.starts_with(scene_code::PREFIX) {
                println!("{}", loaded.to_json());
            } else {
                let code =
                    scene_code::encode(&loaded).map_err(|e| Failure::Invalid(e.to_string()))?;
                println!("{code}");
            }
        }
        Command::Suggest {
            scene,
            targets,
            level,
            seed,
        } => {
            let scene = load(&scene)?;
            let json = suggest::suggest(&scene, &targets, level, seed)
                .map_err(|e| Failure::Invalid(one_line(&e)))?;
            println!("{json}");
        }
        Command::AiStudy {
            out,
            games,
            positions,
            jobs,
            levels,
            snooker,
        } => {
            let size = ai_study::Size {
                games,
                positions,
                jobs,
                levels,
            };
            match snooker.and_then(|r| r.parse::<u8>().ok()) {
                Some(reds) => ai_study::snooker::run(&out, reds, &size)?,
                None => ai_study::run(&out, size)?,
            }
        }
    }
    Ok(())
}
