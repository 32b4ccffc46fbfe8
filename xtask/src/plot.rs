//! Multi-panel line and point plots written as SVG, PNG and the CSV of the plotted data.
//!
//! A [`Figure`] is a grid of [`Panel`]s; each panel holds [`Series`] of (x, y) points drawn as
//! lines, dashed lines, markers or filled polygons. [`Figure::write`] renders the same figure
//! with plotters' SVG and bitmap backends and writes the CSV of exactly the plotted series.

use std::path::{Path, PathBuf};
use std::sync::Once;

use anyhow::{Context, Result, anyhow};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::table::Table;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// A solid polyline through the points.
    Line,
    /// A thick solid polyline (for the graphs of set-valued maps).
    ThickLine,
    /// A dashed polyline.
    Dashed,
    /// Filled circles at the points, no line.
    Points,
    /// Hollow circles at the points (for marking solutions).
    Rings,
    /// A filled translucent polygon through the points.
    Fill,
}

/// One plotted series: points (x, y), a legend label and a CSV column name.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text; an empty label keeps the series out of the legend.
    pub label: String,
    /// Column name of y in the CSV.
    pub column: String,
    /// Abscissae.
    pub x: Vec<f64>,
    /// Ordinates (same length as `x`).
    pub y: Vec<f64>,
    /// How the series is drawn.
    pub mark: Mark,
    /// Index into the colour palette.
    pub color: usize,
    /// Whether the series is written to the CSV (construction lines such as axes are not data).
    pub in_csv: bool,
    /// Text drawn next to each point (empty: none), e.g. the time step Δt of each run.
    pub point_labels: Vec<String>,
}

impl Series {
    /// A solid line series with palette colour `color`.
    pub fn line(label: &str, column: &str, x: Vec<f64>, y: Vec<f64>, color: usize) -> Self {
        Self {
            label: label.to_owned(),
            column: column.to_owned(),
            x,
            y,
            mark: Mark::Line,
            color,
            in_csv: true,
            point_labels: Vec::new(),
        }
    }

    /// The same series drawn with another mark.
    pub fn with_mark(mut self, mark: Mark) -> Self {
        self.mark = mark;
        self
    }

    /// The same series kept out of the CSV.
    pub fn not_data(mut self) -> Self {
        self.in_csv = false;
        self
    }

    /// The same series with a text next to each point (one per point, in order).
    pub fn with_point_labels(mut self, labels: Vec<String>) -> Self {
        self.point_labels = labels;
        self
    }
}

/// Where a panel's legend goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LegendAt {
    /// Upper right corner inside the plot area.
    UpperRight,
    /// Upper left corner.
    UpperLeft,
    /// Lower right corner.
    LowerRight,
    /// Lower left corner.
    LowerLeft,
    /// Middle of the right edge.
    MiddleRight,
    /// No legend.
    None,
}

/// One panel: axes with labels and units, and its series.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Panel title, e.g. "(a) position".
    pub title: String,
    /// x-axis label with unit, e.g. `"t [s]"`.
    pub x_label: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// Column name of x in the CSV.
    pub x_column: String,
    /// The series, drawn in order.
    pub series: Vec<Series>,
    /// Fixed x range; computed from the data when `None`.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; computed from the data when `None`.
    pub y_range: Option<(f64, f64)>,
    /// Legend position.
    pub legend: LegendAt,
    /// Extra room above the data, as a fraction of the data's span (for the legend).
    pub headroom: f64,
}

impl Panel {
    /// An empty panel with a title, axis labels and the CSV name of x.
    pub fn new(title: &str, x_label: &str, y_label: &str, x_column: &str) -> Self {
        Self {
            title: title.to_owned(),
            x_label: x_label.to_owned(),
            y_label: y_label.to_owned(),
            x_column: x_column.to_owned(),
            series: Vec::new(),
            x_range: None,
            y_range: None,
            legend: LegendAt::UpperRight,
            headroom: 0.0,
        }
    }

    /// Leaves `fraction` of the data's span free above the data, for the legend.
    pub fn headroom(mut self, fraction: f64) -> Self {
        self.headroom = fraction;
        self
    }

    /// Adds a series.
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Sets the legend position.
    pub fn legend(mut self, at: LegendAt) -> Self {
        self.legend = at;
        self
    }

    /// Fixes the x range.
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    /// Fixes the y range.
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }
}

/// A figure: a grid of panels with an overall title.
#[derive(Clone, Debug)]
pub struct Figure {
    /// Title drawn above the panels.
    pub title: String,
    /// The panels, row by row.
    pub panels: Vec<Panel>,
    /// Panels per row.
    pub columns: usize,
    /// Width of one panel in pixels.
    pub panel_width: u32,
    /// Height of one panel in pixels.
    pub panel_height: u32,
}

/// Distinct colours that stay apart in print and for common colour-vision deficiencies.
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(230, 159, 0),
    RGBColor(0, 0, 0),
    RGBColor(120, 120, 120),
];

/// The palette colour with index `i` (wrapping).
pub fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

static FONT: Once = Once::new();

/// Registers DejaVu Sans as plotters' "sans-serif" font (once per process).
pub fn register_fonts() {
    FONT.call_once(|| {
        // The font bytes are compiled in and valid; a failure would only mean an unusable
        // font, which the first draw call then reports as an error.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
        let _ = plotters::style::register_font("sans-serif", FontStyle::Bold, dejavu::sans::bold());
    });
}

/// Data range of the finite values in `values`, padded by 5 % (and widened when flat).
pub fn padded_range<'a>(values: impl Iterator<Item = &'a f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &v in values {
        if v.is_finite() {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    let span = hi - lo;
    if span <= 1e-12 * (1.0 + lo.abs().max(hi.abs())) {
        let pad = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return (lo - pad, hi + pad);
    }
    (lo - 0.05 * span, hi + 0.05 * span)
}

impl Figure {
    /// A figure with a title, panels and the number of panels per row.
    pub fn new(title: &str, panels: Vec<Panel>, columns: usize) -> Self {
        Self {
            title: title.to_owned(),
            panels,
            columns: columns.max(1),
            panel_width: 640,
            panel_height: 400,
        }
    }

    /// Sets the size of one panel in pixels.
    pub fn panel_size(mut self, width: u32, height: u32) -> Self {
        self.panel_width = width;
        self.panel_height = height;
        self
    }

    fn rows(&self) -> usize {
        self.panels.len().div_ceil(self.columns).max(1)
    }

    fn size(&self) -> (u32, u32) {
        let cols = self.columns.min(self.panels.len().max(1)) as u32;
        (cols * self.panel_width, self.rows() as u32 * self.panel_height + TITLE_HEIGHT)
    }

    /// Writes `<stem>.svg`, `<stem>.png` and `<stem>.csv` into `dir`; returns the paths.
    ///
    /// # Errors
    /// When a file cannot be written or plotters fails to draw.
    pub fn write(&self, dir: &Path, stem: &str) -> Result<Vec<PathBuf>> {
        let svg = dir.join(format!("{stem}.svg"));
        let png = dir.join(format!("{stem}.png"));
        let csv = dir.join(format!("{stem}.csv"));
        self.write_svg(&svg)?;
        self.write_png(&png)?;
        self.table().write_csv(&csv)?;
        Ok(vec![svg, png, csv])
    }

    /// Renders the figure as SVG.
    ///
    /// # Errors
    /// When plotters fails to draw or the file cannot be written.
    pub fn write_svg(&self, path: &Path) -> Result<()> {
        register_fonts();
        let root = SVGBackend::new(path, self.size()).into_drawing_area();
        self.draw(&root, false).with_context(|| format!("drawing {}", path.display()))?;
        root.present().map_err(|e| anyhow!("writing {}: {e}", path.display()))
    }

    /// Renders the figure as PNG.
    ///
    /// # Errors
    /// When plotters fails to draw or the file cannot be written.
    pub fn write_png(&self, path: &Path) -> Result<()> {
        register_fonts();
        let root = BitMapBackend::new(path, self.size()).into_drawing_area();
        self.draw(&root, true).with_context(|| format!("drawing {}", path.display()))?;
        root.present().map_err(|e| anyhow!("writing {}: {e}", path.display()))
    }

    /// The plotted data as a table: per panel, each run of series that share their abscissae
    /// gets one x column followed by one column per series.
    pub fn table(&self) -> Table {
        let mut table = Table::default();
        for panel in &self.panels {
            let mut last_x: Option<&Vec<f64>> = None;
            for s in panel.series.iter().filter(|s| s.in_csv) {
                if last_x != Some(&s.x) {
                    let name = if table.has_column(&panel.x_column) {
                        format!("{}|{}", panel.x_column, s.column)
                    } else {
                        panel.x_column.clone()
                    };
                    table.push_column(&name, s.x.clone());
                    last_x = Some(&s.x);
                }
                table.push_column(&s.column, s.y.clone());
            }
        }
        table
    }

    /// Draws the figure; `segments` draws solid lines segment by segment (for the bitmap
    /// backend, whose thick polylines spike at sharp turns).
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        segments: bool,
    ) -> Result<()> {
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let (title_area, body) = root.split_vertically(TITLE_HEIGHT);
        title_area
            .titled(&self.title, ("sans-serif", 22).into_font().style(FontStyle::Bold))
            .map_err(|e| anyhow!("{e}"))?;
        let cells = body.split_evenly((self.rows(), self.columns.min(self.panels.len().max(1))));
        for (panel, area) in self.panels.iter().zip(cells.iter()) {
            draw_panel(panel, area, segments)?;
        }
        Ok(())
    }
}

const TITLE_HEIGHT: u32 = 40;

fn draw_panel<DB: DrawingBackend>(
    panel: &Panel,
    area: &DrawingArea<DB, Shift>,
    segments: bool,
) -> Result<()> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("{e}");
    let (x0, x1) =
        panel.x_range.unwrap_or_else(|| padded_range(panel.series.iter().flat_map(|s| s.x.iter())));
    let (y0, y1) = panel.y_range.unwrap_or_else(|| {
        let (lo, hi) = padded_range(panel.series.iter().flat_map(|s| s.y.iter()));
        (lo, hi + panel.headroom * (hi - lo))
    });
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 18))
        .margin(12)
        .margin_right(22)
        .x_label_area_size(48)
        .y_label_area_size(82)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(&panel.x_label)
        .y_desc(&panel.y_label)
        .x_labels(7)
        .y_labels(7)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(e)?;
    let mut any_label = false;
    for s in &panel.series {
        let c = color(s.color);
        let points: Vec<(f64, f64)> =
            s.x.iter()
                .zip(&s.y)
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .map(|(&x, &y)| (x, y))
                .collect();
        let points = match s.mark {
            Mark::Line | Mark::ThickLine | Mark::Dashed => decimate(points, (x0, x1), 1500),
            _ => points,
        };
        let inside = |&(x, y): &(f64, f64)| x >= x0 && x <= x1 && y >= y0 && y <= y1;
        let pieces = || clip_polyline(&points, (x0, x1), (y0, y1));
        let anno = match s.mark {
            Mark::Line | Mark::ThickLine => {
                let style = c.stroke_width(if s.mark == Mark::Line { 2 } else { 4 });
                let pieces = pieces();
                if segments {
                    for piece in &pieces {
                        chart
                            .draw_series(
                                piece.windows(2).map(|w| PathElement::new(vec![w[0], w[1]], style)),
                            )
                            .map_err(e)?;
                    }
                    chart
                        .draw_series(LineSeries::new(Vec::<(f64, f64)>::new(), style))
                        .map_err(e)?
                } else {
                    let mut pieces = pieces;
                    let last = pieces.pop().unwrap_or_default();
                    for piece in pieces {
                        chart.draw_series(LineSeries::new(piece, style)).map_err(e)?;
                    }
                    chart.draw_series(LineSeries::new(last, style)).map_err(e)?
                }
            }
            Mark::Dashed => {
                let mut pieces = pieces();
                let last = pieces.pop().unwrap_or_default();
                for piece in pieces {
                    chart
                        .draw_series(DashedLineSeries::new(piece, 8, 5, c.stroke_width(2)))
                        .map_err(e)?;
                }
                chart
                    .draw_series(DashedLineSeries::new(last, 8, 5, c.stroke_width(2)))
                    .map_err(e)?
            }
            Mark::Points => chart
                .draw_series(
                    points.into_iter().filter(inside).map(|p| Circle::new(p, 3, c.filled())),
                )
                .map_err(e)?,
            Mark::Rings => chart
                .draw_series(
                    points.into_iter().filter(inside).map(|p| Circle::new(p, 7, c.stroke_width(3))),
                )
                .map_err(e)?,
            Mark::Fill => chart
                .draw_series(std::iter::once(Polygon::new(points, c.mix(0.25).filled())))
                .map_err(e)?,
        };
        if !s.label.is_empty() {
            any_label = true;
            let mark = s.mark;
            anno.label(&s.label).legend(move |(x, y)| -> DynElement<'static, DB, (i32, i32)> {
                match mark {
                    Mark::Points => Circle::new((x + 10, y), 4, c.filled()).into_dyn(),
                    Mark::Rings => Circle::new((x + 10, y), 6, c.stroke_width(3)).into_dyn(),
                    Mark::Fill => {
                        Rectangle::new([(x, y - 6), (x + 20, y + 6)], c.mix(0.25).filled())
                            .into_dyn()
                    }
                    Mark::Dashed => plotters::element::DashedPathElement::new(
                        vec![(x, y), (x + 22, y)],
                        6,
                        4,
                        c.stroke_width(2),
                    )
                    .into_dyn(),
                    Mark::Line | Mark::ThickLine => {
                        PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(3)).into_dyn()
                    }
                }
            });
        }
        if !s.point_labels.is_empty() {
            let style = ("sans-serif", 12).into_font().color(&c);
            let labelled =
                s.x.iter()
                    .zip(&s.y)
                    .zip(&s.point_labels)
                    .filter(|((x, y), _)| x.is_finite() && y.is_finite() && inside(&(**x, **y)));
            chart
                .draw_series(labelled.map(|((&x, &y), text)| {
                    EmptyElement::at((x, y)) + Text::new(text.clone(), (5, -14), style.clone())
                }))
                .map_err(e)?;
        }
    }
    if any_label {
        let position = match panel.legend {
            LegendAt::UpperRight => SeriesLabelPosition::UpperRight,
            LegendAt::UpperLeft => SeriesLabelPosition::UpperLeft,
            LegendAt::LowerRight => SeriesLabelPosition::LowerRight,
            LegendAt::LowerLeft => SeriesLabelPosition::LowerLeft,
            LegendAt::MiddleRight => SeriesLabelPosition::MiddleRight,
            LegendAt::None => return Ok(()),
        };
        chart
            .configure_series_labels()
            .position(position)
            .margin(8)
            .label_font(("sans-serif", 14))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(160, 160, 160))
            .draw()
            .map_err(e)?;
    }
    Ok(())
}

/// Thins a long polyline whose x never decreases to at most four points per bucket of
/// `buckets` equal x-intervals (the first, lowest, highest and last, in order), which keeps
/// every extreme visible; other polylines are returned unchanged.
pub fn decimate(points: Vec<(f64, f64)>, (x0, x1): (f64, f64), buckets: usize) -> Vec<(f64, f64)> {
    let monotone = points.windows(2).all(|w| w[1].0 >= w[0].0);
    if !monotone || points.len() <= 4 * buckets || !(x1 > x0) {
        return points;
    }
    let bucket = |x: f64| (((x - x0) / (x1 - x0)) * buckets as f64).floor() as i64;
    let mut out = Vec::with_capacity(4 * buckets + 4);
    let mut start = 0;
    while start < points.len() {
        let b = bucket(points[start].0);
        let mut end = start + 1;
        while end < points.len() && bucket(points[end].0) == b {
            end += 1;
        }
        let chunk = &points[start..end];
        let (mut lo, mut hi) = (0, 0);
        for (i, p) in chunk.iter().enumerate() {
            if p.1 < chunk[lo].1 {
                lo = i;
            }
            if p.1 > chunk[hi].1 {
                hi = i;
            }
        }
        let mut keep = vec![0, lo, hi, chunk.len() - 1];
        keep.sort_unstable();
        keep.dedup();
        out.extend(keep.into_iter().map(|i| chunk[i]));
        start = end;
    }
    out
}

/// Cuts a polyline to the box [x0, x1] × [y0, y1]: the visible pieces, with the crossing
/// points on the box edges (Liang–Barsky clipping of each segment).
pub fn clip_polyline(
    points: &[(f64, f64)],
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Vec<Vec<(f64, f64)>> {
    let mut pieces: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    let inside = |(x, y): (f64, f64)| x >= x0 && x <= x1 && y >= y0 && y <= y1;
    if points.len() == 1 && inside(points[0]) {
        return vec![points.to_vec()];
    }
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let mut visible = true;
        for (p, q) in [(-dx, a.0 - x0), (dx, x1 - a.0), (-dy, a.1 - y0), (dy, y1 - a.1)] {
            if p == 0.0 {
                if q < 0.0 {
                    visible = false;
                    break;
                }
            } else {
                let r = q / p;
                if p < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
            }
        }
        if !visible || t0 > t1 {
            if !current.is_empty() {
                pieces.push(std::mem::take(&mut current));
            }
            continue;
        }
        let start = (a.0 + t0 * dx, a.1 + t0 * dy);
        let end = (a.0 + t1 * dx, a.1 + t1 * dy);
        if current.last() != Some(&start) {
            if !current.is_empty() {
                pieces.push(std::mem::take(&mut current));
            }
            current.push(start);
        }
        current.push(end);
        if t1 < 1.0 {
            pieces.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        pieces.push(current);
    }
    pieces
}

/// Tick label: short decimal, or scientific notation for very small or large magnitudes.
pub fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || a < 1e-12 {
        "0".to_owned()
    } else if !(1e-3..1e5).contains(&a) {
        format!("{v:.1e}")
    } else {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.').to_owned();
        if s == "-0" { "0".to_owned() } else { s }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_short() {
        assert_eq!(tick(0.25), "0.25");
        assert_eq!(tick(2.0), "2");
        assert_eq!(tick(-1e-5), "-1.0e-5");
        assert_eq!(tick(1e-14), "0");
        assert_eq!(tick(123456.0), "1.2e5");
    }

    #[test]
    fn decimation_keeps_the_extremes() {
        let points: Vec<(f64, f64)> = (0..10_000)
            .map(|k| (k as f64, if k == 5_003 { 9.0 } else { (k % 7) as f64 }))
            .collect();
        let thin = decimate(points.clone(), (0.0, 10_000.0), 100);
        assert!(thin.len() <= 400, "{}", thin.len());
        assert!(thin.contains(&(5_003.0, 9.0)));
        assert_eq!(thin.first(), points.first());
        assert_eq!(thin.last(), points.last());
        // A phase portrait (x not monotone) is left alone.
        let back = vec![(0.0, 0.0), (1.0, 1.0), (0.5, 2.0)];
        assert_eq!(decimate(back.clone(), (0.0, 1.0), 1), back);
    }

    #[test]
    fn clipping_cuts_at_the_box_edges() {
        // A line from (-1, -1) to (3, 3) in the unit box: one piece from (0, 0) to (1, 1).
        let pieces = clip_polyline(&[(-1.0, -1.0), (3.0, 3.0)], (0.0, 1.0), (0.0, 1.0));
        assert_eq!(pieces, vec![vec![(0.0, 0.0), (1.0, 1.0)]]);
        // Leaving and re-entering gives two pieces.
        let pieces = clip_polyline(&[(0.5, 0.5), (0.5, 2.0), (0.8, 0.5)], (0.0, 1.0), (0.0, 1.0));
        assert_eq!(pieces.len(), 2);
        assert_eq!(pieces[0], vec![(0.5, 0.5), (0.5, 1.0)]);
        assert!((pieces[1][0].1 - 1.0).abs() < 1e-12 && pieces[1][1] == (0.8, 0.5));
        // Entirely outside.
        assert!(clip_polyline(&[(2.0, 2.0), (3.0, 3.0)], (0.0, 1.0), (0.0, 1.0)).is_empty());
    }

    #[test]
    fn padded_range_handles_flat_and_nan() {
        assert_eq!(padded_range([f64::NAN].iter()), (-1.0, 1.0));
        let (lo, hi) = padded_range([2.0, 2.0].iter());
        assert!(lo < 2.0 && hi > 2.0);
        let (lo, hi) = padded_range([0.0, 10.0].iter());
        assert!((lo + 0.5).abs() < 1e-12 && (hi - 10.5).abs() < 1e-12);
    }

    #[test]
    fn table_shares_x_columns() {
        let x = vec![0.0, 1.0];
        let fig = Figure::new(
            "t",
            vec![
                Panel::new("(a)", "t [s]", "y [m]", "t")
                    .with(Series::line("a", "y_a", x.clone(), vec![1.0, 2.0], 0))
                    .with(Series::line("b", "y_b", x.clone(), vec![3.0, 4.0], 1)),
                Panel::new("(b)", "t [s]", "v [m/s]", "t").with(Series::line(
                    "c",
                    "v",
                    vec![0.0, 0.5, 1.0],
                    vec![5.0, 6.0, 7.0],
                    0,
                )),
            ],
            2,
        );
        let t = fig.table();
        assert_eq!(t.headers(), vec!["t", "y_a", "y_b", "t|v", "v"]);
        assert_eq!(t.rows(), 3);
    }
}
