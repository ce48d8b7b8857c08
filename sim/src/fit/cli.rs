//! The `fit` subcommand's arguments.

use std::path::PathBuf;

use breakshot_shared::physics::CushionModel;

use super::recording::Units;
use super::Options;

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
    /// Nelder–Mead iterations of each short strike search.
    #[arg(long, default_value_t = 80)]
    iters: u64,
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
    let options = Options {
        units,
        cushion,
        fit_cloth: !args.strikes_only,
        iters: args.iters,
        ..Options::default()
    };
    super::run(&args.recordings, &args.out, options).map_err(Error::Other)
}
