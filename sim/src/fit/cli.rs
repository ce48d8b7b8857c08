//! The `fit` subcommand's arguments.

use std::path::PathBuf;

use breakshot_shared::physics::{CushionModel, Params, TableKind};
use breakshot_shared::scene::physics_over_defaults;

use super::cloth::Loss;
use super::recording::Units;
use super::{pool_start, Options, Start};

#[derive(clap::Args)]
pub struct Args {
    /// Recordings file (the format of the real-shot recordings).
    recordings: PathBuf,
    /// Folder for fit.md, fit.csv, paths.png and rmse.png.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// `m` when positions are already in metres (default: the recordings' own units).
    #[arg(long, value_name = "UNIT")]
    units: Option<String>,
    /// Cushion model: han2005, mathavan2010, stronge or simple.
    #[arg(long, value_name = "MODEL", default_value = "han2005")]
    cushion: String,
    /// Fit only the strikes, under the start parameters.
    #[arg(long)]
    strikes_only: bool,
    /// The parameters the fit starts from: pool (the pool cloth's constants on the carom
    /// table), defaults (the carom table's own), or a JSON file of physics parameters as in
    /// a scene's `physics` (over the carom table's defaults).
    #[arg(long, value_name = "pool|defaults|FILE.json", default_value = "pool")]
    start: String,
    /// Cross-validate instead: deal the shots into K folds, fit the shared parameters
    /// without each fold and only the strikes of its shots under them (docs/reality.md).
    #[arg(long, value_name = "K")]
    folds: Option<usize>,
    /// Nelder–Mead iterations of each short strike search.
    #[arg(long, default_value_t = 80)]
    iters: u64,
    /// What the shared-parameter fit minimises over the shots' RMSEs: robust (Cauchy's
    /// loss, scale 10 cm: a shot far off pulls little) or mean.
    #[arg(long, value_name = "robust|mean", default_value = "robust")]
    loss: String,
}

pub enum Error {
    Invalid(String),
    Other(anyhow::Error),
}

pub fn run(args: Args) -> Result<(), Error> {
    let units = match args.units.as_deref() {
        None => Units::Recording,
        Some("m") => Units::Metres,
        Some(other) => return Err(Error::Invalid(format!("--units {other}: only m is known"))),
    };
    let cushion: CushionModel =
        serde_json::from_value(serde_json::Value::String(args.cushion.clone()))
            .map_err(|_| Error::Invalid(format!("--cushion {}: unknown model", args.cushion)))?;
    if args.iters == 0 {
        return Err(Error::Invalid("--iters must be at least 1".into()));
    }
    let loss = match args.loss.as_str() {
        "robust" => Loss::Robust,
        "mean" => Loss::Mean,
        other => return Err(Error::Invalid(format!("--loss {other}: robust or mean"))),
    };
    let (start_from, start) = start_params(&args.start)?;
    let options = Options {
        units,
        cushion,
        start_from,
        start,
        fit_cloth: !args.strikes_only,
        iters: args.iters,
        loss,
        ..Options::default()
    };
    match args.folds {
        None => super::run(&args.recordings, &args.out, options),
        Some(k) if k < 2 => return Err(Error::Invalid(format!("--folds {k}: at least 2"))),
        Some(_) if args.strikes_only => {
            return Err(Error::Invalid(
                "--folds fits the shared parameters: not with --strikes-only".into(),
            ))
        }
        Some(k) => super::cross_validate(&args.recordings, &args.out, options, k),
    }
    .map_err(Error::Other)
}

/// The parameters `--start` names: `pool`, `defaults`, or a file of a scene's `physics`
/// object, read over the carom table's defaults and checked like a scene's.
pub fn start_params(arg: &str) -> Result<(Start, Params), Error> {
    match arg {
        "pool" => Ok((Start::Pool, pool_start())),
        "defaults" => Ok((Start::Defaults, Params::for_table(TableKind::Carom))),
        path => {
            let bad = |why: String| Error::Invalid(format!("--start {path}: {why}"));
            let text = std::fs::read_to_string(path).map_err(|e| {
                bad(format!(
                    "not pool, defaults or a readable parameters file ({e})"
                ))
            })?;
            let value: serde_json::Value =
                serde_json::from_str(&text).map_err(|e| bad(format!("not JSON ({e})")))?;
            let serde_json::Value::Object(overrides) = value else {
                return Err(bad("must be a JSON object of physics parameters".into()));
            };
            let params = physics_over_defaults(TableKind::Carom, overrides).map_err(bad)?;
            params.validate().map_err(bad)?;
            Ok((Start::File, params))
        }
    }
}
