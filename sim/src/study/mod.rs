//! The accuracy/cost study: what the event-based engine's exactness costs, against
//! fixed-step integration at several steps, on one workload; and what each effect costs.
//!
//! `run_study` does the work and returns plain data; `report` and `plot` turn it into the
//! published files.

pub mod effects;
pub mod fixed_step;
pub mod methods;
pub mod metrics;
pub mod plot;
pub mod report;
pub mod trace;
pub mod workload;

use std::path::Path;

use anyhow::Context;
use breakshot_shared::physics::{Shot, Simulator};
use indicatif::{ProgressBar, ProgressStyle};

use effects::{DisabledCheck, RungCost};
use methods::{Method, Timed};
use metrics::{compare, first_collision, saw_collision, Comparison};
use workload::{Case, Category};

/// One method on one shot, compared with the reference.
#[derive(Clone, Debug)]
pub struct Row {
    pub case: usize,
    pub method: usize,
    pub seconds: f64,
    pub steps: u64,
    pub deepest_overlap: f64,
    pub comparison: Comparison,
    /// The first ball–ball collision is the reference's.
    pub first_collision_matches: bool,
    /// The cue ball met ball 1 if and only if it did in the reference.
    pub object_contact_matches: bool,
}

/// Everything the study measured.
pub struct Study {
    pub cases: Vec<Case>,
    pub methods: Vec<Method>,
    pub rows: Vec<Row>,
    pub effects: Vec<RungCost>,
    pub disabled: DisabledCheck,
}

/// Runs the whole study, showing progress.
pub fn run_study() -> anyhow::Result<Study> {
    let cases = workload::workload();
    let methods = Method::all();
    let effect_shots: Vec<Shot> = cases
        .iter()
        .filter(|c| c.category.is_break())
        .map(|c| c.shot.clone())
        .collect();
    let total = cases.len() * methods.len() + effects::ladder().len() * effect_shots.len() + 1;
    let bar = ProgressBar::new(total as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{msg:28} [{elapsed_precise}] {wide_bar} {pos}/{len} (eta {eta})",
        )
        .context("progress bar template")?,
    );
    let mut sim = Simulator::new();
    let mut rows = Vec::new();
    for (ci, case) in cases.iter().enumerate() {
        bar.set_message(case.name.split(':').next().unwrap_or("").to_string());
        let reference = methods::run(Method::Event, &case.shot, &mut sim)
            .with_context(|| format!("shot {}", case.name))?;
        for (mi, &method) in methods.iter().enumerate() {
            let timed = if method == Method::Event {
                reference.clone()
            } else {
                methods::run(method, &case.shot, &mut sim)
                    .with_context(|| format!("shot {} with {}", case.name, method.label()))?
            };
            rows.push(row(ci, mi, &reference, &timed));
            bar.inc(1);
        }
    }
    bar.set_message("cost of each effect");
    let effects = effects::cost_of_effects(&effect_shots, || bar.inc(1))?;
    bar.set_message("disabled effects");
    let stun = cases
        .iter()
        .find(|c| c.category == Category::SingleSpin)
        .map(|c| c.shot.clone())
        .context("the workload has no open-cloth shot")?;
    let disabled = effects::disabled_effects_cost_nothing(&stun)?;
    bar.inc(1);
    bar.finish_with_message("done");
    Ok(Study {
        cases,
        methods,
        rows,
        effects,
        disabled,
    })
}

fn row(case: usize, method: usize, reference: &Timed, timed: &Timed) -> Row {
    let (r, t) = (&reference.trace, &timed.trace);
    Row {
        case,
        method,
        seconds: timed.seconds,
        steps: timed.steps,
        deepest_overlap: timed.deepest_overlap,
        comparison: compare(r, t),
        first_collision_matches: first_collision(r) == first_collision(t),
        object_contact_matches: saw_collision(r, 0, 1) == saw_collision(t, 0, 1),
    }
}

/// Runs the study and writes `accuracy-cost.md`, `.csv` and `.png` into `out`.
pub fn run(out: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let study = run_study()?;
    let md = out.join("accuracy-cost.md");
    std::fs::write(&md, report::markdown(&study))
        .with_context(|| format!("writing {}", md.display()))?;
    let csv = out.join("accuracy-cost.csv");
    std::fs::write(&csv, report::csv(&study))
        .with_context(|| format!("writing {}", csv.display()))?;
    let png = out.join("accuracy-cost.png");
    plot::draw(&study, &png).with_context(|| format!("drawing {}", png.display()))?;
    println!(
        "wrote {}, {} and {}",
        md.display(),
        csv.display(),
        png.display()
    );
    Ok(())
}
