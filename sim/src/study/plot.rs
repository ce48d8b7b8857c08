//! The study's plot: final-position error against CPU time per shot, log–log, one line per
//! method (each point a step), for the breaks and for the other shots.

use std::path::Path;

use anyhow::anyhow;
use plotters::prelude::*;

use super::methods::Method;
use super::report::summarize;
use super::workload::Category;
use super::Study;
use crate::chart::{canvas, register_font, FONT};

/// Errors below this (mm) are drawn on the axis: the reference's own error is exactly 0.
const ERROR_FLOOR: f64 = 1e-4;

/// A point per method: (median µs per shot, mean error mm, step label).
type Line = Vec<(f64, f64, &'static str)>;

fn lines(study: &Study, categories: &[Category]) -> (Line, Line, (f64, f64)) {
    let mut fixed = Line::new();
    let mut toi = Line::new();
    let mut event = (0.0, ERROR_FLOOR);
    for (m, method) in study.methods.iter().enumerate() {
        let s = summarize(study.rows_of(m, categories).into_iter());
        let point = (s.median_us, s.mean_mm.max(ERROR_FLOOR), method.step_label());
        match method {
            Method::Event => event = (s.median_us, ERROR_FLOOR),
            Method::Fixed(f) if f.toi => toi.push(point),
            Method::Fixed(_) => fixed.push(point),
        }
    }
    (fixed, toi, event)
}

/// Draws the plot into a PNG at `path`.
pub fn draw(study: &Study, path: &Path) -> anyhow::Result<()> {
    register_font()?;
    let breaks = [Category::Break8, Category::Break9];
    let others: Vec<Category> = Category::ALL
        .into_iter()
        .filter(|c| !c.is_break())
        .collect();
    let sets = [
        (
            "breaks",
            lines(study, &breaks),
            [RGBColor(200, 30, 30), RGBColor(30, 60, 200)],
        ),
        (
            "other shots",
            lines(study, &others),
            [RGBColor(240, 140, 40), RGBColor(40, 170, 200)],
        ),
    ];
    let mut x_max: f64 = 1.0;
    let mut x_min: f64 = f64::INFINITY;
    let mut y_max: f64 = 1.0;
    for (_, (fixed, toi, event), _) in &sets {
        for p in fixed.iter().chain(toi) {
            x_max = x_max.max(p.0);
            x_min = x_min.min(p.0);
            y_max = y_max.max(p.1);
        }
        x_min = x_min.min(event.0);
    }
    let x_range = (x_min / 3.0).max(1e-3)..x_max * 3.0;
    let y_range = ERROR_FLOOR / 2.0..y_max * 5.0;

    let root = canvas(path, (1400, 900))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Accuracy against cost: fixed steps vs the event-based engine",
            (FONT, 30),
        )
        .margin(25)
        .margin_right(70)
        .x_label_area_size(70)
        .y_label_area_size(100)
        .build_cartesian_2d(x_range.log_scale(), y_range.log_scale())
        .map_err(|e| anyhow!("{e}"))?;
    chart
        .configure_mesh()
        .x_desc("median CPU time per shot (µs)")
        .y_desc("mean final-position error (mm)")
        .x_label_formatter(&|x| format!("{x}"))
        .y_label_formatter(&|y| format!("{y}"))
        .axis_desc_style((FONT, 22))
        .label_style((FONT, 18))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;

    for (k, (set, (fixed, toi, event), colours)) in sets.iter().enumerate() {
        // Step labels above the TOI line's points and below the plain line's, so that they
        // stay apart where the lines meet.
        for (line, colour, family, shift) in [
            (fixed, colours[0], "fixed step", 0.55),
            (toi, colours[1], "fixed step + TOI", 1.3),
        ] {
            let style = ShapeStyle::from(colour).stroke_width(3);
            chart
                .draw_series(LineSeries::new(line.iter().map(|p| (p.0, p.1)), style))
                .map_err(|e| anyhow!("{e}"))?
                .label(format!("{family}, {set}"))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 30, y)], style));
            chart
                .draw_series(
                    line.iter()
                        .map(|p| Circle::new((p.0, p.1), 6, colour.filled())),
                )
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .draw_series(line.iter().map(|p| {
                    Text::new(
                        p.2.to_string(),
                        (p.0 * 1.08, p.1 * shift),
                        (FONT, 16).into_font(),
                    )
                }))
                .map_err(|e| anyhow!("{e}"))?;
        }
        let marker = ShapeStyle::from(BLACK).filled();
        chart
            .draw_series(std::iter::once(TriangleMarker::new(*event, 12, marker)))
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .draw_series(std::iter::once(Text::new(
                format!("event-based, {set} (exact: error 0)"),
                (event.0 * 1.1, event.1 * if k == 0 { 4.0 } else { 1.6 }),
                (FONT, 16).into_font(),
            )))
            .map_err(|e| anyhow!("{e}"))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font((FONT, 18))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}
