//! `breakshot-sim fit`: the simulator measured against recorded shots (docs/reality.md).
//!
//! For each recording, the cue strike whose simulation best matches it; then the parameters
//! every shot shares, fitted once over all recordings with the strikes held, alternating
//! with warm-started strike refits; then the report (fit.md, fit.csv, plots).

pub mod cli;
pub mod cloth;
pub mod crossval;
mod plot;
pub mod recording;
mod report;
pub mod strike;
#[cfg(test)]
mod tests;

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use anyhow::Context;
use breakshot_shared::physics::{CushionModel, Models, Params, TableKind};
use indicatif::{ProgressBar, ProgressStyle};

use recording::{Recording, Units};
use strike::StrikeFit;

/// Nelder–Mead iterations of each shared-parameter fit.
const CLOTH_ITERS: u64 = 100;

/// Which parameters a fit starts from (`--start`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    /// The pool cloth's constants on the carom table ([`pool_start`]).
    Pool,
    /// The carom table's own defaults (the constants fitted to the shared recordings).
    Defaults,
    /// A scene-style `physics` object read from a file.
    File,
}

impl Start {
    /// How the report names it.
    pub fn describe(self) -> &'static str {
        match self {
            Start::Pool => "pool cloth (pooltool 0.6.0's constants) on the carom table",
            Start::Defaults => "the carom table's defaults",
            Start::File => "the parameters file given",
        }
    }
}

/// How a fit is run.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    pub units: Units,
    pub cushion: CushionModel,
    /// Where the parameters start, and their values.
    pub start_from: Start,
    pub start: Params,
    /// Fit the shared parameters too (otherwise only the strikes, under the start values).
    pub fit_cloth: bool,
    /// Nelder–Mead iterations of each short strike search (the refinement takes twice).
    pub iters: u64,
    /// Rounds of shared-parameter fit and strike refit.
    pub rounds: usize,
    /// What the shared-parameter fit minimises.
    pub loss: cloth::Loss,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            units: Units::Recording,
            cushion: CushionModel::default(),
            start_from: Start::Pool,
            start: pool_start(),
            fit_cloth: true,
            iters: 80,
            rounds: 2,
            loss: cloth::Loss::default(),
        }
    }
}

/// What a fit found.
pub struct Fit {
    pub recordings: Vec<Recording>,
    pub options: Options,
    /// The parameters the fit starts from (`Options::start`).
    pub start: Params,
    /// The fitted shared parameters (equal to `start` without the cloth fit).
    pub fitted: Params,
    /// Each shot's best strike under `start`, and under `fitted`.
    pub start_fits: Vec<StrikeFit>,
    pub fitted_fits: Vec<StrikeFit>,
    /// Wall-clock seconds of each stage: start fits, shared fit rounds, total.
    pub seconds: Vec<(String, f64)>,
}

/// The `pool` start: the carom table's balls and cushion height, with the cloth, ball and
/// cushion constants that the pool tables use (pooltool 0.6.0's, from the literature).
pub fn pool_start() -> Params {
    let carom = Params::for_table(TableKind::Carom);
    Params {
        ball_radius: carom.ball_radius,
        ball_mass: carom.ball_mass,
        cushion_height: carom.cushion_height,
        ..Params::default()
    }
}

fn read(path: &Path, units: Units) -> anyhow::Result<Vec<Recording>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    recording::parse(&text, units)
}

/// Reads `path`, cross-validates the fit in `folds` folds, and writes the report into `out`.
pub fn cross_validate(
    path: &Path,
    out: &Path,
    options: Options,
    folds: usize,
) -> anyhow::Result<()> {
    let cv = crossval::run(read(path, options.units)?, options, folds, true)?;
    crossval::write(&cv, out)?;
    eprintln!(
        "held-out median RMSE {:.1} cm over {} shots in {folds} folds; wrote {}",
        100.0 * report::quantile(&rmses(&cv.held_out), 0.5),
        cv.held_out.len(),
        out.join("fit.md").display()
    );
    Ok(())
}

/// Reads `path`, fits, and writes the report into `out`.
pub fn run(path: &Path, out: &Path, options: Options) -> anyhow::Result<()> {
    let recordings = read(path, options.units)?;
    let fit = fit(recordings, options, true)?;
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    report::write(&fit, out)?;
    plot::draw(&fit, out)?;
    eprintln!(
        "median RMSE {:.1} cm (start parameters {:.1} cm); wrote {}",
        100.0 * report::quantile(&rmses(&fit.fitted_fits), 0.5),
        100.0 * report::quantile(&rmses(&fit.start_fits), 0.5),
        out.join("fit.md").display()
    );
    Ok(())
}

pub fn rmses(fits: &[StrikeFit]) -> Vec<f64> {
    fits.iter().map(|f| f.rmse).collect()
}

/// The engine's models a fit of `options` simulates with.
fn models(options: &Options) -> Models {
    Models {
        cushion: options.cushion,
        ..Models::default()
    }
}

/// Each shot's strike searched again under `params`: from its `previous` strike (found under
/// other parameters) and from scratch, the better kept. A round of the fit does this for
/// every shot; a cross-validation for the shots it holds out, so that they are searched as
/// hard as the shots the constants were fitted on.
fn refit_strikes(
    recordings: &[Recording],
    params: &Params,
    previous: &[StrikeFit],
    options: &Options,
    bar: &ProgressBar,
) -> anyhow::Result<Vec<StrikeFit>> {
    let models = models(options);
    each(recordings, bar, |rec, k| {
        let warm = strike::fit(rec, params, models, Some(&previous[k]), options.iters)?;
        let cold = strike::fit(rec, params, models, None, options.iters)?;
        Ok(if cold.rmse < warm.rmse { cold } else { warm })
    })
}

/// Runs the fit on `recordings`, showing progress when `show`.
pub fn fit(recordings: Vec<Recording>, options: Options, show: bool) -> anyhow::Result<Fit> {
    let models = models(&options);
    let start = options.start;
    // Every start position must be valid before the long work begins.
    for rec in &recordings {
        strike::base_shot(rec, &start, models)?;
    }
    let n = recordings.len();
    let stages = 1 + if options.fit_cloth { options.rounds } else { 0 };
    let bar = if show {
        ProgressBar::new((n * stages) as u64)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{msg:28} [{elapsed_precise}] {wide_bar} {pos}/{len}")
            .context("progress bar template")?,
    );
    let clock = Instant::now();
    let mut seconds = Vec::new();
    bar.set_message("strikes, start parameters");
    let start_fits = each(&recordings, &bar, |rec, _| {
        strike::fit(rec, &start, models, None, options.iters)
    })?;
    seconds.push((
        "strikes, start parameters".into(),
        clock.elapsed().as_secs_f64(),
    ));
    let mut fitted = start;
    let mut fits = start_fits.clone();
    if options.fit_cloth {
        for round in 1..=options.rounds {
            let t0 = Instant::now();
            bar.set_message(format!("shared parameters, round {round}"));
            fitted = cloth::fit(
                &recordings,
                &fits,
                &fitted,
                models,
                CLOTH_ITERS,
                options.loss,
            );
            fits = refit_strikes(&recordings, &fitted, &fits, &options, &bar)?;
            seconds.push((format!("round {round}"), t0.elapsed().as_secs_f64()));
        }
    }
    bar.finish_and_clear();
    seconds.push(("total".into(), clock.elapsed().as_secs_f64()));
    Ok(Fit {
        recordings,
        options,
        start,
        fitted,
        start_fits,
        fitted_fits: fits,
        seconds,
    })
}

/// `f` on every recording, on as many threads as the machine offers, results in order.
fn each<F>(recs: &[Recording], bar: &ProgressBar, f: F) -> anyhow::Result<Vec<StrikeFit>>
where
    F: Fn(&Recording, usize) -> anyhow::Result<StrikeFit> + Sync,
{
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(recs.len().max(1));
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<anyhow::Result<StrikeFit>>>> =
        Mutex::new((0..recs.len()).map(|_| None).collect());
    std::thread::scope(|scope| {
        for _ in 0..threads {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(rec) = recs.get(k) else { break };
                let r = f(rec, k);
                if let Ok(mut all) = results.lock() {
                    all[k] = Some(r);
                }
                bar.inc(1);
            });
        }
    });
    let all = results
        .into_inner()
        .map_err(|_| anyhow::anyhow!("a fitting thread failed"))?;
    all.into_iter()
        .enumerate()
        .map(|(k, r)| r.unwrap_or_else(|| Err(anyhow::anyhow!("shot {k} was not fitted"))))
        .collect()
}
