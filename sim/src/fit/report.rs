//! fit.md and fit.csv: per-shot RMSE, its distribution, the fitted parameters, timings.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Context;
use breakshot_shared::physics::Params;

use super::cloth::{values, RANGES};
use super::recording::Recording;
use super::strike::StrikeFit;
use super::{rmses, Fit};

/// The best published median RMSE over such recordings (m).
pub const PUBLISHED_MEDIAN: f64 = 0.223;

/// The `q` quantile (linear interpolation) of `v`.
pub fn quantile(v: &[f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let pos = q * (s.len() - 1) as f64;
    let lo = pos.floor() as usize;
    let hi = pos.ceil() as usize;
    s[lo] + (s[hi] - s[lo]) * (pos - lo as f64)
}

/// Median, quartiles, count under 10 cm, mean.
pub struct Summary {
    pub median: f64,
    pub q1: f64,
    pub q3: f64,
    pub under_10cm: usize,
    pub mean: f64,
}

pub fn summarize(v: &[f64]) -> Summary {
    Summary {
        median: quantile(v, 0.5),
        q1: quantile(v, 0.25),
        q3: quantile(v, 0.75),
        under_10cm: v.iter().filter(|&&r| r < 0.1).count(),
        mean: v.iter().sum::<f64>() / v.len().max(1) as f64,
    }
}

pub fn write(fit: &Fit, out: &Path) -> anyhow::Result<()> {
    std::fs::write(out.join("fit.csv"), csv(fit)).context("writing fit.csv")?;
    std::fs::write(out.join("fit.md"), markdown(fit)).context("writing fit.md")?;
    write_physics(&fit.fitted, &out.join("physics.json"))
}

/// Writes `params` as a scene's `physics` object, which `fit --start FILE.json` (and a
/// scene) can read back.
pub fn write_physics(params: &Params, path: &Path) -> anyhow::Result<()> {
    let text = serde_json::to_string_pretty(params).context("encoding the parameters")?;
    std::fs::write(path, text + "\n").with_context(|| format!("writing {}", path.display()))
}

/// The CSV columns that follow a shot's id and RMSEs, in fit.csv of a fit and of a
/// cross-validation alike.
pub const STRIKE_CSV_HEADER: &str =
    "angle_deg,speed_m_s,tip_side,tip_height,delay_s,samples,duration_s";

/// A shot's values for [`STRIKE_CSV_HEADER`]: its fitted strike and its recording's extent.
pub fn strike_csv(f: &StrikeFit, rec: &Recording) -> String {
    format!(
        "{:.4},{:.4},{:.4},{:.4},{:.4},{},{:.2}",
        f.angle_deg,
        f.speed,
        f.tip[0],
        f.tip[1],
        f.delay,
        rec.samples(),
        rec.end()
    )
}

fn csv(fit: &Fit) -> String {
    let mut s = format!("id,rmse_m,rmse_start_m,{STRIKE_CSV_HEADER}\n");
    for (k, rec) in fit.recordings.iter().enumerate() {
        let f = &fit.fitted_fits[k];
        let (start, strike) = (fit.start_fits[k].rmse, strike_csv(f, rec));
        let _ = writeln!(s, "{},{:.6},{start:.6},{strike}", rec.id, f.rmse);
    }
    s
}

fn markdown(fit: &Fit) -> String {
    let start = summarize(&rmses(&fit.start_fits));
    let fitted = summarize(&rmses(&fit.fitted_fits));
    let n = fit.recordings.len();
    let mut s = String::new();
    let _ = writeln!(s, "# Fit of simulated strikes to {n} recorded shots\n");
    let _ = writeln!(
        s,
        "Cushion model `{:?}`; RMSE over all balls at all recorded sample times (m). Start \
         parameters: {}; the fitted ones are in `physics.json`{}.\n",
        fit.options.cushion,
        fit.options.start_from.describe(),
        if fit.options.fit_cloth {
            format!(", fitted by minimising {}", fit.options.loss.describe())
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        s,
        "| parameters | median | quartiles | under 10 cm | mean |\n|---|---|---|---|---|"
    );
    for (name, x) in [("start", &start), ("fitted", &fitted)] {
        let _ = writeln!(
            s,
            "| {name} | {:.3} | {:.3}–{:.3} | {}/{n} | {:.3} |",
            x.median, x.q1, x.q3, x.under_10cm, x.mean
        );
    }
    let _ = writeln!(
        s,
        "| published best (182 shots) | {PUBLISHED_MEDIAN:.3} | 0.148–0.356 | 25/182 | — |\n"
    );
    let _ = writeln!(s, "## Shared parameters\n");
    let _ = writeln!(s, "| name | start | fitted | range |\n|---|---|---|---|");
    let (a, b) = (values(&fit.start), values(&fit.fitted));
    for (k, (name, lo, hi)) in RANGES.iter().enumerate() {
        let _ = writeln!(s, "| `{name}` | {} | {:.5} | {lo}–{hi} |", a[k], b[k]);
    }
    let _ = writeln!(s, "\n## Time\n");
    for (stage, secs) in &fit.seconds {
        let _ = writeln!(s, "- {stage}: {secs:.1} s");
    }
    let _ = writeln!(
        s,
        "\n## Shots\n\n| id | RMSE (m) | start RMSE (m) | aim (°) | cue speed (m/s) | tip side | tip height | strike at (s) |\n|---|---|---|---|---|---|---|---|"
    );
    for (k, rec) in fit.recordings.iter().enumerate() {
        let f = &fit.fitted_fits[k];
        let _ = writeln!(
            s,
            "| {} | {:.3} | {:.3} | {:.2} | {:.3} | {:.2} | {:.2} | {:.3} |",
            rec.id,
            f.rmse,
            fit.start_fits[k].rmse,
            f.angle_deg,
            f.speed,
            f.tip[0],
            f.tip[1],
            f.delay
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_interpolate() {
        let v = [4.0, 1.0, 3.0, 2.0];
        assert_eq!(quantile(&v, 0.0), 1.0);
        assert_eq!(quantile(&v, 1.0), 4.0);
        assert_eq!(quantile(&v, 0.5), 2.5);
        assert!(quantile(&[], 0.5).is_nan());
    }
}
