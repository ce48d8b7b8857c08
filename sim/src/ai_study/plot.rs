//! The budget plot: shot success against simulations per decision (log scale).

use std::path::Path;

use anyhow::anyhow;
use plotters::prelude::*;

use crate::chart::{canvas, register_font, FONT};

/// Draws `(simulations, success)` points into a PNG at `path`.
pub fn draw(points: &[(f64, f64)], path: &Path) -> anyhow::Result<()> {
    register_font()?;
    let x_max = points.iter().map(|p| p.0).fold(10.0, f64::max) * 2.0;
    let x_min = points
        .iter()
        .map(|p| p.0)
        .fold(f64::INFINITY, f64::min)
        .max(1.0)
        / 2.0;
    let root = canvas(path, (1000, 650))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Shot success against search budget (level 5 noise)",
            (FONT, 26),
        )
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(60)
        .build_cartesian_2d((x_min..x_max).log_scale(), 0.0..100.0)
        .map_err(|e| anyhow!("{e}"))?;
    chart
        .configure_mesh()
        .x_desc("simulations per decision (mean)")
        .y_desc("shots that kept the table or won (%)")
        .label_style((FONT, 16))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    let series: Vec<(f64, f64)> = points.iter().map(|&(s, p)| (s, 100.0 * p)).collect();
    chart
        .draw_series(LineSeries::new(series.clone(), BLUE.stroke_width(2)))
        .map_err(|e| anyhow!("{e}"))?;
    chart
        .draw_series(series.iter().map(|&p| Circle::new(p, 5, BLUE.filled())))
        .map_err(|e| anyhow!("{e}"))?;
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}
