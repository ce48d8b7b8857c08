//! Cross-validation of the fit (`fit --folds K`): the shots are dealt into K folds; for each
//! fold the shared parameters are fitted on the other folds' shots, and the fold's own
//! shots have only their strikes fitted under those parameters, searched as hard as the
//! fitted shots' (a strike found under the start parameters, then, once a round, searched
//! again under the fold's constants from the last one and from scratch, as each round of the
//! fit searches every shot), so every shot's RMSE comes from constants fitted without it.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::{bail, Context};
use breakshot_shared::physics::Params;
use indicatif::ProgressBar;

use super::cloth::{values, RANGES};
use super::recording::Recording;
use super::report::{
    strike_csv, summarize, write_physics, Summary, PUBLISHED_MEDIAN, STRIKE_CSV_HEADER,
};
use super::strike::StrikeFit;
use super::{fit, refit_strikes, rmses, Options};

/// One fold: the parameters fitted without its shots, and the RMSE of the shots they were
/// fitted on (in-sample, for comparison).
pub struct Fold {
    pub fitted: Params,
    pub seen: Vec<f64>,
    pub seconds: f64,
}

/// What a cross-validation found.
pub struct CrossValidation {
    pub recordings: Vec<Recording>,
    pub options: Options,
    /// The fold of each shot, in the recordings' order.
    pub fold_of: Vec<usize>,
    pub folds: Vec<Fold>,
    /// Each shot's strike fitted under the parameters of the fold that did not see it.
    pub held_out: Vec<StrikeFit>,
}

/// The fold of each of `n` shots: dealt in turn, shot `i` into fold `i mod k`, so the folds
/// differ in size by one at most and the result does not depend on anything but the order.
pub fn deal(n: usize, k: usize) -> Vec<usize> {
    (0..n).map(|i| i % k).collect()
}

/// Cross-validates the fit of `options` over `recordings` in `k` folds.
pub fn run(
    recordings: Vec<Recording>,
    options: Options,
    k: usize,
    show: bool,
) -> anyhow::Result<CrossValidation> {
    if k < 2 || k > recordings.len() {
        bail!(
            "--folds {k}: between 2 and the number of shots ({})",
            recordings.len()
        );
    }
    let fold_of = deal(recordings.len(), k);
    let part = |fold: usize, inside: bool| -> Vec<Recording> {
        recordings
            .iter()
            .zip(&fold_of)
            .filter(|(_, &f)| (f == fold) == inside)
            .map(|(r, _)| r.clone())
            .collect()
    };
    let mut folds = Vec::with_capacity(k);
    let mut held_out: Vec<Option<StrikeFit>> = vec![None; recordings.len()];
    for fold in 0..k {
        let clock = Instant::now();
        if show {
            eprintln!("fold {}/{k}", fold + 1);
        }
        let train = fit(
            part(fold, false),
            Options {
                fit_cloth: true,
                ..options
            },
            show,
        )?;
        // The fold's shots are searched as the fitted ones were: a strike under the start
        // parameters, then, once a round, searched again under the fold's constants, from
        // the last one and from scratch.
        let test = fit(
            part(fold, true),
            Options {
                fit_cloth: false,
                ..options
            },
            show,
        )?;
        let mut shots = test.start_fits;
        for _ in 0..options.rounds {
            shots = refit_strikes(
                &test.recordings,
                &train.fitted,
                &shots,
                &options,
                &ProgressBar::hidden(),
            )?;
        }
        let mut shots = shots.into_iter();
        for (slot, _) in held_out
            .iter_mut()
            .zip(&fold_of)
            .filter(|(_, &f)| f == fold)
        {
            *slot = shots.next();
        }
        folds.push(Fold {
            fitted: train.fitted,
            seen: rmses(&train.fitted_fits),
            seconds: clock.elapsed().as_secs_f64(),
        });
    }
    let held_out = held_out
        .into_iter()
        .enumerate()
        .map(|(i, f)| f.with_context(|| format!("shot {i} was not held out")))
        .collect::<anyhow::Result<Vec<_>>>()?;
    Ok(CrossValidation {
        recordings,
        options,
        fold_of,
        folds,
        held_out,
    })
}

/// Writes fit.md (the held-out figures, each fold's parameters), fit.csv (one row per shot,
/// its RMSE under the parameters fitted without it) and each fold's `physics-K.json`.
pub fn write(cv: &CrossValidation, out: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let mut csv = format!("id,fold,rmse_m,{STRIKE_CSV_HEADER}\n");
    for (i, rec) in cv.recordings.iter().enumerate() {
        let f = &cv.held_out[i];
        let (fold, strike) = (cv.fold_of[i] + 1, strike_csv(f, rec));
        let _ = writeln!(csv, "{},{fold},{:.6},{strike}", rec.id, f.rmse);
    }
    std::fs::write(out.join("fit.csv"), csv).context("writing fit.csv")?;
    std::fs::write(out.join("fit.md"), markdown(cv)).context("writing fit.md")?;
    for (k, fold) in cv.folds.iter().enumerate() {
        write_physics(&fold.fitted, &out.join(format!("physics-{}.json", k + 1)))?;
    }
    Ok(())
}

fn row(s: &mut String, name: &str, x: &Summary, n: usize) {
    let _ = writeln!(
        s,
        "| {name} | {:.3} | {:.3}–{:.3} | {}/{n} | {:.3} |",
        x.median, x.q1, x.q3, x.under_10cm, x.mean
    );
}

fn markdown(cv: &CrossValidation) -> String {
    let n = cv.recordings.len();
    let k = cv.folds.len();
    let held = summarize(&rmses(&cv.held_out));
    let seen: Vec<f64> = cv
        .folds
        .iter()
        .flat_map(|f| f.seen.iter().copied())
        .collect();
    let seen = summarize(&seen);
    let mut s = String::new();
    let _ = writeln!(s, "# Cross-validated fit over {n} recorded shots\n");
    let _ = writeln!(
        s,
        "Cushion model `{:?}`; {k} folds (shot i in fold i mod {k}); start parameters: {}. \
         For each fold the shared parameters are fitted on the other folds' shots (minimising \
         {}), then only the strikes of the fold's shots under them. RMSE over all balls at \
         all recorded sample times (m).\n",
        cv.options.cushion,
        cv.options.start_from.describe(),
        cv.options.loss.describe()
    );
    let _ = writeln!(
        s,
        "| RMSE | median | quartiles | under 10 cm | mean |\n|---|---|---|---|---|"
    );
    row(&mut s, "held out (each shot once)", &held, n);
    row(
        &mut s,
        "in sample (shots each fold was fitted on)",
        &seen,
        seen_count(cv),
    );
    let _ = writeln!(
        s,
        "| published best (182 shots, in sample) | {PUBLISHED_MEDIAN:.3} | 0.148–0.356 | 25/182 | — |\n"
    );
    let _ = writeln!(s, "## Shared parameters per fold\n");
    let mut header = String::from("| fold | shots held out |");
    let mut rule = String::from("|---|---|");
    for (name, _, _) in RANGES {
        let _ = write!(header, " `{name}` |");
        rule.push_str("---|");
    }
    let _ = writeln!(s, "{header} time (s) |\n{rule}---|");
    for (f, fold) in cv.folds.iter().enumerate() {
        let held: Vec<&str> = cv
            .recordings
            .iter()
            .zip(&cv.fold_of)
            .filter(|(_, &g)| g == f)
            .map(|(r, _)| r.id.as_str())
            .collect();
        let _ = write!(s, "| {} | {} |", f + 1, held.join(", "));
        for v in values(&fold.fitted) {
            let _ = write!(s, " {v:.5} |");
        }
        let _ = writeln!(s, " {:.0} |", fold.seconds);
    }
    let _ = writeln!(
        s,
        "\n## Shots\n\n| id | fold | held-out RMSE (m) |\n|---|---|---|"
    );
    for (i, rec) in cv.recordings.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {} | {:.3} |",
            rec.id,
            cv.fold_of[i] + 1,
            cv.held_out[i].rmse
        );
    }
    s
}

fn seen_count(cv: &CrossValidation) -> usize {
    cv.folds.iter().map(|f| f.seen.len()).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shots_are_dealt_in_turn() {
        assert_eq!(deal(7, 3), vec![0, 1, 2, 0, 1, 2, 0]);
        let folds = deal(40, 8);
        for f in 0..8 {
            assert_eq!(folds.iter().filter(|&&g| g == f).count(), 5);
        }
    }
}
