//! Rough simulation counts of the parts of a search, made before the search knows how many
//! candidates it will have: only for the progress a stepped search reports, never for a
//! decision. Once the candidates are known, the search counts its trials exactly.

use super::candidates::{variants, Breadth};
use super::caroms;
use super::search::{trials_left, Schedule};

/// Window probes per pot route, as `candidates` fans them.
const PROBES_PER_ROUTE: usize = 13;
/// Safeties and kicks a table typically offers besides the pots (they cost no simulation to
/// make, only to try).
const OTHER_CANDIDATES: usize = 40;
/// Share of a three-cushion fan's strokes that score, each then tried four times nudged.
const SCORING_SHARE: f64 = 0.1;

/// A pool shot's search from the table as it lies: making its candidates, then their trials,
/// a look-ahead costing `look_ahead` simulations.
pub(super) fn shot(breadth: &Breadth, schedule: &Schedule, look_ahead: usize) -> usize {
    let variants = variants(1.0, breadth).len();
    let probes = 2 * breadth.pots * PROBES_PER_ROUTE;
    let aims = breadth.pots * variants * breadth.corrections;
    let candidates = breadth.pots * variants + OTHER_CANDIDATES;
    probes + aims + trials(schedule, candidates, look_ahead)
}

/// A three-cushion stroke's search: its fans, then the trials of the strokes kept (a carom
/// table has no pot to look ahead to).
pub(super) fn caroms(breadth: &Breadth, schedule: &Schedule) -> usize {
    let strokes = caroms::fans(breadth) * caroms::directions(breadth);
    let nudges = (strokes as f64 * SCORING_SHARE * caroms::NUDGES_DEG.len() as f64) as usize;
    strokes + nudges + trials(schedule, caroms::KEEP, 0)
}

fn trials(schedule: &Schedule, candidates: usize, look_ahead: usize) -> usize {
    let (plain, deep) = trials_left(schedule, 0, candidates);
    plain + deep * (1 + look_ahead)
}
