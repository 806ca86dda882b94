//! The growth-rate map of Fig. 12.

use super::*;

impl GrowthMap {
    /// A growth-rate map of `chart`, no markers.
    pub fn new(title: &str, chart: ChartResult) -> GrowthMap {
        GrowthMap { title: title.to_string(), chart, markers: Vec::new() }
    }

    /// With vertical marker lines at φ (rad/s), each labelled at the top.
    pub fn with_markers(mut self, markers: Vec<(f64, String)>) -> GrowthMap {
        self.markers = markers;
        self
    }

    /// Min and max growth rate (1/s) over the unstable points, if any.
    pub fn growth_range(&self) -> Option<(f64, f64)> {
        self.chart.points.iter().filter(|p| unstable(p) && p.growth_rate.is_finite()).map(|p| p.growth_rate).fold(
            None,
            |acc, g| match acc {
                None => Some((g, g)),
                Some((lo, hi)) => Some((f64::min(lo, g), f64::max(hi, g))),
            },
        )
    }
}

/// The layout's plotting area is the map's (the colour bar beside it is not a legend).
impl Drawing for GrowthMap {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>, layout: &Cell<Layout>) -> Result<(), PlotError> {
        root.fill(&WHITE).map_err(err)?;
        let area = style::titled(&root, &self.title)?;
        let failed = failed_count(&self.chart);
        let (legend_area, area) = area.split_vertically(if failed > 0 { 34 } else { 0 });
        if failed > 0 {
            let font = (style::FONT, style::LEGEND_SIZE)
                .into_font()
                .into_text_style(&legend_area)
                .pos(Pos::new(HPos::Left, VPos::Center));
            let yc = legend_area.dim_in_pixel().1 as i32 / 2;
            style::draw_key(&legend_area, &Key::Cross, 90, yc)?;
            legend_area.draw(&Text::new(failed_label(failed), (124, yc), font)).map_err(err)?;
        }
        let width = area.dim_in_pixel().0;
        let (main, bar) = area.split_horizontally(width.saturating_sub(135));

        // Colour scale: the unstable growth rates, in GROWTH_LEVELS levels.
        let range = self.growth_range();
        let (lo, hi) = match range {
            Some((lo, hi)) if hi > lo => (lo, hi),
            Some((g, _)) => {
                let d = (0.05 * g.abs()).max(1e-9);
                (g - d, g + d)
            }
            None => (0.0, 1.0),
        };
        let top = (GROWTH_LEVELS - 1) as f64;
        let level = |g: f64| {
            let t = if g.is_finite() { (g - lo) / (hi - lo) } else { 1.0 };
            (t.clamp(0.0, 1.0) * top).round() as usize
        };
        let color = |k: usize| -> RGBAColor { ViridisRGB.get_color_normalized(k as f64, 0.0, top).to_rgba() };

        let (x, y) = ranges(std::iter::once(&self.chart));
        let mut plot = axes(&main, x, y, 10)?;
        let cells = blocks(&self.chart, |p| unstable(p).then(|| level(p.growth_rate)));
        draw_blocks(&mut plot, &self.chart, &cells, |&k| color(k))?;
        draw_failed(&mut plot, &self.chart)?;
        draw_markers(&mut plot, &self.markers, &mut clip::Occupied::default())?;
        draw_frame(&mut plot)?;
        layout.set(Layout { plot: area_box(plot.plotting_area()), legend: None });

        // Colour bar, aligned with the main plotting area (same margins and x-label area).
        let mut cbar = style::colour_bar(&bar, (lo, hi), GROWTH_LABEL, style::AXIS_LABEL_SIZE - 2)?;
        if range.is_some() {
            cbar.draw_series((0..GROWTH_LEVELS).map(|k| {
                let t0 = ((k as f64 - 0.5) / top).max(0.0);
                let t1 = ((k as f64 + 0.5) / top).min(1.0);
                Rectangle::new([(0.0, lo + t0 * (hi - lo)), (1.0, lo + t1 * (hi - lo))], color(k).filled())
            }))
            .map_err(err)?;
        }
        draw_frame(&mut cbar)?;
        root.present().map_err(err)
    }
}
