//! The fit's plots: recorded against simulated paths for the best, median and worst shots
//! (paths.png), and the RMSE of every shot, sorted, with the start and the fitted
//! parameters (rmse.png).

use std::path::Path;

use anyhow::anyhow;
use plotters::prelude::*;

use super::report::PUBLISHED_MEDIAN;
use super::strike::Problem;
use super::{rmses, Fit};
use crate::chart::{register_font, FONT};
use breakshot_shared::physics::{Models, TableKind};

/// Ball colours: the cue ball (white, drawn grey), the others yellow and red.
const COLOURS: [RGBColor; 3] = [
    RGBColor(90, 90, 90),
    RGBColor(220, 170, 0),
    RGBColor(210, 30, 30),
];

fn err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("drawing: {e:?}")
}

pub fn draw(fit: &Fit, out: &Path) -> anyhow::Result<()> {
    register_font()?;
    paths(fit, &out.join("paths.png"))?;
    distribution(fit, &out.join("rmse.png"))
}

/// Indices of the best, median and worst shots under the fitted parameters.
pub fn picks(fit: &Fit) -> [usize; 3] {
    let mut order: Vec<usize> = (0..fit.recordings.len()).collect();
    order.sort_by(|&a, &b| fit.fitted_fits[a].rmse.total_cmp(&fit.fitted_fits[b].rmse));
    let last = order.len().saturating_sub(1);
    [order[0], order[last / 2], order[last]]
}

fn paths(fit: &Fit, path: &Path) -> anyhow::Result<()> {
    let (w, l) = TableKind::Carom.size().unwrap_or((1.42, 2.84));
    let root = BitMapBackend::new(path, (1500, 900)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let models = Models {
        cushion: fit.options.cushion,
        ..Models::default()
    };
    let panels = root.split_evenly((1, 3));
    for (panel, (label, k)) in panels
        .iter()
        .zip(["best", "median", "worst"].into_iter().zip(picks(fit)))
    {
        let rec = &fit.recordings[k];
        let f = &fit.fitted_fits[k];
        let problem = Problem::new(rec, &fit.fitted, models)?;
        let outcome = problem.outcome(f)?;
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!("{label}: shot {} (RMSE {:.1} cm)", rec.id, 100.0 * f.rmse),
                (FONT, 20),
            )
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(40)
            .build_cartesian_2d(0.0..w, 0.0..l)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("x (m)")
            .y_desc("y (m)")
            .label_style((FONT, 12))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(0.0, 0.0), (w, l)],
                RGBColor(0, 110, 60).stroke_width(2),
            )))
            .map_err(err)?;
        for (i, track) in rec.balls.iter().enumerate() {
            // The cue ball first in the colour order, then the others.
            let c = match i.cmp(&rec.cue) {
                std::cmp::Ordering::Equal => 0,
                std::cmp::Ordering::Less => i + 1,
                std::cmp::Ordering::Greater => i,
            };
            let colour = COLOURS[c.min(2)];
            let recorded: Vec<(f64, f64)> = track.pos.iter().map(|p| (p.x, p.y)).collect();
            chart
                .draw_series(LineSeries::new(recorded, colour.stroke_width(2)))
                .map_err(err)?
                .label(format!("ball {} recorded", track.name))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 15, y)], colour.stroke_width(2))
                });
            let steps = (rec.end() / 0.02).ceil() as usize;
            let simulated: Vec<(f64, f64)> = (0..=steps)
                .map(|s| {
                    let p = outcome.state_at(i, s as f64 * 0.02 - f.delay).pos;
                    (p.x, p.y)
                })
                .collect();
            chart
                .draw_series(
                    simulated
                        .into_iter()
                        .step_by(3)
                        .map(|p| Circle::new(p, 2, colour.mix(0.5).filled())),
                )
                .map_err(err)?;
        }
        chart
            .configure_series_labels()
            .label_font((FONT, 12))
            .background_style(WHITE.mix(0.8))
            .draw()
            .map_err(err)?;
    }
    root.present().map_err(err)?;
    Ok(())
}

fn distribution(fit: &Fit, path: &Path) -> anyhow::Result<()> {
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let mut start = rmses(&fit.start_fits);
    let mut fitted = rmses(&fit.fitted_fits);
    start.sort_by(f64::total_cmp);
    fitted.sort_by(f64::total_cmp);
    let n = start.len();
    let top = start
        .iter()
        .chain(&fitted)
        .fold(PUBLISHED_MEDIAN, |a, &b| a.max(b))
        * 100.0
        * 1.05;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "RMSE per shot, sorted (line: best published median)",
            (FONT, 22),
        )
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..1.0, 0.0..top)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("fraction of shots")
        .y_desc("RMSE (cm)")
        .label_style((FONT, 14))
        .draw()
        .map_err(err)?;
    let frac = |k: usize| (k as f64 + 0.5) / n.max(1) as f64;
    for (values, colour, label) in [
        (&start, RGBColor(150, 150, 150), "start parameters"),
        (&fitted, RGBColor(30, 60, 200), "fitted parameters"),
    ] {
        let points: Vec<(f64, f64)> = values
            .iter()
            .enumerate()
            .map(|(k, &r)| (frac(k), 100.0 * r))
            .collect();
        chart
            .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))
            .map_err(err)?
            .label(label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 15, y)], colour.stroke_width(2))
            });
        chart
            .draw_series(
                points
                    .into_iter()
                    .map(|p| Circle::new(p, 3, colour.filled())),
            )
            .map_err(err)?;
    }
    chart
        .draw_series(LineSeries::new(
            [
                (0.0, 100.0 * PUBLISHED_MEDIAN),
                (1.0, 100.0 * PUBLISHED_MEDIAN),
            ],
            RGBColor(200, 30, 30).stroke_width(1),
        ))
        .map_err(err)?
        .label("22.3 cm (published median)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], RGBColor(200, 30, 30)));
    chart
        .configure_series_labels()
        .label_font((FONT, 14))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}
