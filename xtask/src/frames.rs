//! Frame strips (drawings of a mechanism at chosen instants, with a caption under each) as
//! SVG and PNG, and animated SVGs of the motion.
//!
//! A frame of a run is made by [`frame`] from the model's own drawing (`AnyModel::draw`) at a
//! row of its record, painted by role ([`paint`]); [`motion`] makes the frames of an
//! animation. The report's strips and `cargo xtask frames` all go through these.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow};
use moreau_kinematics::ContactKinematics;
use moreau_models::{AnyModel, Drawing, ModelKind, Role};
use moreau_stepper::{ContactState, Mechanism, Record};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::plot::{clip_polyline, register_fonts};

/// Paint of a drawing element by its role.
pub fn paint(role: Role) -> Paint {
    let p = |stroke: (u8, u8, u8), width: u32, fill: Option<(u8, u8, u8)>| Paint {
        stroke,
        width,
        fill,
    };
    match role {
        Role::Ground | Role::Guide => p((60, 60, 60), 3, None),
        Role::Pole => p((90, 90, 90), 1, Some((215, 215, 215))),
        Role::Sleeve => p((0, 84, 147), 2, Some((120, 170, 220))),
        Role::Bird => p((150, 90, 0), 2, Some((240, 200, 110))),
        Role::Beak => p((150, 40, 0), 2, Some((230, 120, 50))),
        Role::Joint => p((0, 0, 0), 2, Some((255, 255, 255))),
        Role::Crank => p((0, 100, 60), 3, None),
        Role::Rod => p((0, 84, 147), 3, None),
        Role::Slider => p((0, 84, 147), 2, Some((120, 170, 220))),
        Role::Cam => p((90, 60, 20), 2, Some((225, 205, 170))),
        Role::Follower => p((0, 84, 147), 2, Some((120, 170, 220))),
        Role::Ball => p((0, 84, 147), 2, Some((120, 170, 220))),
        Role::ContactPoint => p((200, 0, 0), 2, Some((230, 30, 30))),
        _ => p((0, 0, 0), 1, None),
    }
}

/// A model's drawing as frame shapes, in layers: the filled circles of bodies (disks, balls)
/// first, then the lines and polygons in their order, then the other circles (pins,
/// bearings, pivots), and the contact markers last, on top. A disk's radius, which shows its
/// rotation, is a line over its disk.
pub fn shapes(drawing: &Drawing) -> Vec<Shape> {
    let body_disk = |role: Role| {
        paint(role).fill.is_some() && !matches!(role, Role::Joint | Role::ContactPoint)
    };
    let mut layers: [Vec<Shape>; 4] = Default::default();
    for c in drawing.circles.iter().filter(|c| body_disk(c.role)) {
        layers[0].push(Shape::Circle { center: c.center, radius: c.radius, paint: paint(c.role) });
    }
    for l in &drawing.polylines {
        let s = Shape::Poly { points: l.points.clone(), closed: l.closed, paint: paint(l.role) };
        layers[if l.role == Role::ContactPoint { 3 } else { 1 }].push(s);
    }
    for c in drawing.circles.iter().filter(|c| !body_disk(c.role)) {
        let s = Shape::Circle { center: c.center, radius: c.radius, paint: paint(c.role) };
        layers[if c.role == Role::ContactPoint { 3 } else { 2 }].push(s);
    }
    layers.into_iter().flatten().collect()
}

/// The contacts closed in row `row` of a run of `model`, one flag per listed contact: in a
/// row after the first, each contact active at the midpoint of the row's last step or not
/// open at its end (`record.active`, `record.state`); in row 0, which no step has reached,
/// each contact whose gap at the initial state is at most [`closing_tolerance`].
pub fn closed_in_row(model: &AnyModel, record: &Record, row: usize) -> Vec<bool> {
    let n = model.num_contacts();
    if row == 0 {
        let (q, t) = (&record.q[0], record.t[0]);
        let tol = closing_tolerance(model, q, t);
        return (0..n).map(|i| model.normal_gap(i, q, t) <= tol).collect();
    }
    let (active, states) = (record.active.get(row), record.state.get(row));
    (0..n)
        .map(|i| {
            let a = active.and_then(|a| a.get(i)).copied().unwrap_or(false);
            let s = states.and_then(|s| s.get(i)).copied().unwrap_or(ContactState::Open);
            a || s != ContactState::Open
        })
        .collect()
}

/// The gap at or below which a contact counts as closed at a state: a declared mechanism's
/// gap tolerance (`Multibody::gap_tolerance`, which its steps take too), 1e-9 of the
/// drawing's size for a report model.
pub fn closing_tolerance(model: &AnyModel, q: &[f64], t: f64) -> f64 {
    match model {
        AnyModel::Declared(m) => m.gap_tolerance(),
        _ => 1e-9 * model.draw(q, t).bounds().map_or(1.0, |b| b.width().max(b.height())),
    }
}

/// Where the contacts of a declared mechanism whose contacts are detected at each step are
/// closed at (q, t): the midpoint of the two surface points of every contact the detection
/// finds with a gap at most the mechanism's gap tolerance, in the order of their identities.
/// `None` for a mechanism whose contacts are listed (the record holds those).
pub fn detected_contacts(model: &AnyModel, q: &[f64], t: f64) -> Option<Vec<[f64; 2]>> {
    let AnyModel::Declared(m) = model else { return None };
    let structure = Mechanism::body_structure(m)?;
    let margin = m.gap_tolerance();
    let mut found = Vec::new();
    structure.detect(q, t, margin, &mut found);
    Some(
        found
            .iter()
            .filter(|c| c.point.g_n <= margin)
            .filter_map(|c| m.locate_contact(c.id, q, t, margin))
            .map(|l| {
                let (a, b) = (l.geometry.point_a, l.geometry.point_b);
                [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
            })
            .collect(),
    )
}

/// The frame of row `row` of a run of `model`: the model's drawing at (q, t) of the row, with
/// `caption` under it and the strip's window.
///
/// The report's models mark their closed contacts in their own drawings; a declared
/// mechanism's drawing shows its bodies and joints only, so its contacts closed in the row
/// ([`closed_in_row`]) are marked here, at the midpoint of their two surface points, and,
/// when its contacts are detected at each step, those the detection finds closed at the row's
/// state ([`detected_contacts`]).
pub fn frame(model: &AnyModel, record: &Record, row: usize, caption: Vec<String>) -> Frame {
    let (q, t) = (&record.q[row], record.t[row]);
    let mut drawing = model.draw(q, t);
    if model.kind() == ModelKind::Declared {
        // 1.2 % of the drawing's size, and at most a quarter of its smallest disk, so that the
        // markers of a pile of small disks do not hide them.
        let size = drawing.bounds().map_or(1.0, |b| b.width().max(b.height()));
        let smallest = drawing
            .circles
            .iter()
            .filter(|c| c.role == Role::Ball && c.radius > 0.0)
            .map(|c| c.radius)
            .fold(f64::INFINITY, f64::min);
        let radius = (0.012 * size).min(0.25 * smallest);
        let mut points: Vec<[f64; 2]> = model
            .contact_points(q, t)
            .into_iter()
            .zip(closed_in_row(model, record, row))
            .filter_map(|(p, closed)| closed.then_some(p))
            .collect();
        points.extend(detected_contacts(model, q, t).unwrap_or_default());
        for p in points {
            drawing.circle(Role::ContactPoint, p, radius);
        }
    }
    Frame { t, shapes: shapes(&drawing), caption, window: None }
}

/// Rows of a record at `count` evenly spaced times from `t0` to `t1` (the first row at or
/// after each time), for an animation.
pub fn motion_rows(record: &Record, t0: f64, t1: f64, count: usize) -> Vec<usize> {
    (0..count)
        .filter_map(|j| {
            let t = t0 + (t1 - t0) * j as f64 / (count.max(2) - 1) as f64;
            record.t.iter().position(|&tk| tk >= t - 1e-12)
        })
        .collect()
}

/// Frames of the motion of a run at `count` evenly spaced rows between `t0` and `t1`, each
/// captioned with its time, for an animation.
pub fn motion(model: &AnyModel, record: &Record, t0: f64, t1: f64, count: usize) -> Vec<Frame> {
    motion_rows(record, t0, t1, count)
        .into_iter()
        .map(|k| frame(model, record, k, vec![format!("t = {:.4} s", record.t[k])]))
        .collect()
}

/// One drawn shape in world coordinates (metres, y up).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A polyline, closed into a polygon when `closed`.
    Poly {
        /// Vertices (m).
        points: Vec<[f64; 2]>,
        /// Whether the last vertex joins the first.
        closed: bool,
        /// Outline and fill.
        paint: Paint,
    },
    /// A circle.
    Circle {
        /// Centre (m).
        center: [f64; 2],
        /// Radius (m).
        radius: f64,
        /// Outline and fill.
        paint: Paint,
    },
}

/// How a shape is painted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Paint {
    /// Outline colour (r, g, b).
    pub stroke: (u8, u8, u8),
    /// Outline width in pixels.
    pub width: u32,
    /// Fill colour, if filled.
    pub fill: Option<(u8, u8, u8)>,
}

/// A drawing at one instant with the lines of text written under it.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Time of the drawing (s).
    pub t: f64,
    /// The shapes, drawn in order.
    pub shapes: Vec<Shape>,
    /// Caption lines (time, contact state, ...).
    pub caption: Vec<String>,
    /// World window [x0, y0, x1, y1] of this frame (a camera that follows the mechanism);
    /// the strip's window when `None`. Shapes are cut to the window.
    pub window: Option<[f64; 4]>,
}

/// A row (or grid) of frames sharing one world window.
#[derive(Clone, Debug)]
pub struct Strip {
    /// Title above the frames.
    pub title: String,
    /// The frames, left to right.
    pub frames: Vec<Frame>,
    /// Frames per row.
    pub columns: usize,
    /// Width of one frame cell in pixels.
    pub cell_width: u32,
    /// Height of the drawing part of a cell in pixels (the caption goes below it).
    pub cell_height: u32,
    /// World window [x0, y0, x1, y1]; the union of all shapes (padded) when `None`.
    pub window: Option<[f64; 4]>,
}

/// Height of the title's band (pixels).
pub const TITLE: u32 = 40;

/// Height of a caption line (pixels).
pub const LINE: u32 = 18;

/// Bounding box [x0, y0, x1, y1] of the shapes of all frames, padded by 5 %.
pub fn bounds<'a>(frames: impl IntoIterator<Item = &'a Frame>) -> [f64; 4] {
    let mut b = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
    let mut add = |x: f64, y: f64| {
        if x.is_finite() && y.is_finite() {
            b[0] = b[0].min(x);
            b[1] = b[1].min(y);
            b[2] = b[2].max(x);
            b[3] = b[3].max(y);
        }
    };
    for f in frames {
        for s in &f.shapes {
            match s {
                Shape::Poly { points, .. } => points.iter().for_each(|p| add(p[0], p[1])),
                Shape::Circle { center, radius, .. } => {
                    add(center[0] - radius, center[1] - radius);
                    add(center[0] + radius, center[1] + radius);
                }
            }
        }
    }
    if !b[0].is_finite() {
        return [-1.0, -1.0, 1.0, 1.0];
    }
    let pad = 0.05 * (b[2] - b[0]).max(b[3] - b[1]).max(1e-9);
    [b[0] - pad, b[1] - pad, b[2] + pad, b[3] + pad]
}

/// Maps world coordinates into a `w × h` pixel box with equal scales, y up, centred.
#[derive(Clone, Copy, Debug)]
struct View {
    scale: f64,
    ox: f64,
    oy: f64,
    window: [f64; 4],
}

impl View {
    fn new(window: [f64; 4], w: u32, h: u32, margin: f64) -> Self {
        let (ww, wh) = (window[2] - window[0], window[3] - window[1]);
        let scale = ((w as f64 - 2.0 * margin) / ww).min((h as f64 - 2.0 * margin) / wh);
        let ox = (w as f64 - scale * ww) / 2.0;
        let oy = (h as f64 - scale * wh) / 2.0;
        Self { scale, ox, oy, window }
    }

    fn map(&self, p: [f64; 2]) -> (f64, f64) {
        (
            self.ox + (p[0] - self.window[0]) * self.scale,
            self.oy + (self.window[3] - p[1]) * self.scale,
        )
    }
}

/// Cuts a polygon to a window (Sutherland–Hodgman).
fn clip_polygon(points: &[[f64; 2]], w: [f64; 4]) -> Vec<[f64; 2]> {
    let mut out = points.to_vec();
    // Each edge: keep points with sign * (coordinate − bound) >= 0.
    for (axis, bound, sign) in [(0, w[0], 1.0), (0, w[2], -1.0), (1, w[1], 1.0), (1, w[3], -1.0)] {
        let input = std::mem::take(&mut out);
        let n = input.len();
        for i in 0..n {
            let (a, b) = (input[i], input[(i + 1) % n]);
            let (da, db) = (sign * (a[axis] - bound), sign * (b[axis] - bound));
            if da >= 0.0 {
                out.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                let t = da / (da - db);
                out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
            }
        }
    }
    out
}

/// The parts of a shape inside a window.
pub fn clip_shape(shape: &Shape, w: [f64; 4]) -> Vec<Shape> {
    match shape {
        Shape::Poly { points, closed: true, paint } => {
            let p = clip_polygon(points, w);
            if p.len() < 3 {
                Vec::new()
            } else {
                vec![Shape::Poly { points: p, closed: true, paint: *paint }]
            }
        }
        Shape::Poly { points, closed: false, paint } => {
            let pts: Vec<(f64, f64)> = points.iter().map(|p| (p[0], p[1])).collect();
            clip_polyline(&pts, (w[0], w[2]), (w[1], w[3]))
                .into_iter()
                .map(|piece| Shape::Poly {
                    points: piece.into_iter().map(|(x, y)| [x, y]).collect(),
                    closed: false,
                    paint: *paint,
                })
                .collect()
        }
        Shape::Circle { center, radius, .. } => {
            let inside = center[0] + radius >= w[0]
                && center[0] - radius <= w[2]
                && center[1] + radius >= w[1]
                && center[1] - radius <= w[3];
            if inside { vec![shape.clone()] } else { Vec::new() }
        }
    }
}

fn rgb(c: (u8, u8, u8)) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

/// Size of the captions' font (pixels).
pub const CAPTION: u32 = 14;

/// Size of the title's font (pixels).
pub const TITLE_FONT: u32 = 22;

/// Width in pixels of `text` in the sans-serif font of `size` pixels (bold or not), as the
/// strip draws it.
pub fn text_width(text: &str, size: u32, bold: bool) -> u32 {
    register_fonts();
    let font = ("sans-serif", size).into_font();
    let font = if bold { font.style(FontStyle::Bold) } else { font };
    // Without the font, a generous estimate of 0.65 em a character.
    font.box_size(text)
        .map_or_else(|_| (0.65 * size as f64 * text.chars().count() as f64) as u32, |(w, _)| w)
}

/// `line` cut into lines at most `width` pixels wide in the captions' font: at the `·` that
/// separate its items first, then at spaces; a word wider than `width` keeps a line alone.
pub fn wrap(line: &str, width: u32) -> Vec<String> {
    let fits = |s: &str| text_width(s, CAPTION, false) <= width;
    if fits(line) {
        return vec![line.to_owned()];
    }
    let mut out: Vec<String> = Vec::new();
    let join = |pieces: Vec<&str>, sep: &str, out: &mut Vec<String>| {
        let mut current = String::new();
        for piece in pieces {
            let candidate = if current.is_empty() {
                piece.to_owned()
            } else {
                format!("{current}{sep}{piece}")
            };
            if current.is_empty() || fits(&candidate) {
                current = candidate;
            } else {
                out.push(std::mem::replace(&mut current, piece.to_owned()));
            }
        }
        if !current.is_empty() {
            out.push(current);
        }
    };
    let mut items = Vec::new();
    join(line.split(" · ").collect(), " · ", &mut items);
    for item in items {
        if fits(&item) {
            out.push(item);
        } else {
            join(item.split(' ').collect(), " ", &mut out);
        }
    }
    out
}

impl Strip {
    fn window(&self) -> [f64; 4] {
        self.window.unwrap_or_else(|| bounds(&self.frames))
    }

    /// Each frame's caption, its lines cut to the cell's width.
    fn captions(&self) -> Vec<Vec<String>> {
        let width = self.cell_width.saturating_sub(8).max(1);
        self.frames
            .iter()
            .map(|f| f.caption.iter().flat_map(|l| wrap(l, width)).collect())
            .collect()
    }

    fn caption_lines(&self) -> u32 {
        self.captions().iter().map(Vec::len).max().unwrap_or(0) as u32
    }

    fn rows(&self) -> usize {
        self.frames.len().div_ceil(self.columns.max(1)).max(1)
    }

    fn cell(&self) -> (u32, u32) {
        (self.cell_width, self.cell_height + LINE * self.caption_lines() + 10)
    }

    /// Columns of cells actually drawn.
    fn cols(&self) -> u32 {
        self.columns.max(1).min(self.frames.len().max(1)) as u32
    }

    /// The picture's size in pixels: the cells, widened to the title's width when it is
    /// wider, and the title above them.
    pub fn size(&self) -> (u32, u32) {
        let (cw, ch) = self.cell();
        let title = text_width(&self.title, TITLE_FONT, true) + 24;
        ((self.cols() * cw).max(title), self.rows() as u32 * ch + TITLE)
    }

    /// Writes `<stem>.svg` and `<stem>.png` (the strip) and `<stem>_anim.svg` (the animation
    /// of `motion`, one frame every `frame_seconds` of playback); returns the paths.
    ///
    /// # Errors
    /// When a file cannot be written.
    pub fn write(
        &self,
        dir: &Path,
        stem: &str,
        motion: &[Frame],
        frame_seconds: f64,
    ) -> Result<Vec<PathBuf>> {
        let mut files = self.write_still(dir, stem)?;
        let anim = dir.join(format!("{stem}_anim.svg"));
        let window = bounds(motion.iter().chain(&self.frames));
        std::fs::write(&anim, animated_svg(&self.title, motion, window, frame_seconds))
            .with_context(|| format!("writing {}", anim.display()))?;
        files.push(anim);
        Ok(files)
    }

    /// Writes `<stem>.svg` and `<stem>.png` (the strip alone); returns the paths.
    ///
    /// # Errors
    /// When a file cannot be written.
    pub fn write_still(&self, dir: &Path, stem: &str) -> Result<Vec<PathBuf>> {
        register_fonts();
        let svg = dir.join(format!("{stem}.svg"));
        let png = dir.join(format!("{stem}.png"));
        {
            let root = SVGBackend::new(&svg, self.size()).into_drawing_area();
            self.draw(&root).with_context(|| format!("drawing {}", svg.display()))?;
            root.present().map_err(|e| anyhow!("writing {}: {e}", svg.display()))?;
        }
        {
            let root = BitMapBackend::new(&png, self.size()).into_drawing_area();
            self.draw(&root).with_context(|| format!("drawing {}", png.display()))?;
            root.present().map_err(|e| anyhow!("writing {}: {e}", png.display()))?;
        }
        Ok(vec![svg, png])
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("{e}");
        root.fill(&WHITE).map_err(e)?;
        let (title, body) = root.split_vertically(TITLE);
        title
            .titled(&self.title, ("sans-serif", TITLE_FONT).into_font().style(FontStyle::Bold))
            .map_err(e)?;
        // The cells, centred under a title wider than they are.
        let pad = (self.size().0 - self.cols() * self.cell_width) / 2;
        let body = body.margin(0, 0, pad, pad);
        let cells = body.split_evenly((self.rows(), self.cols() as usize));
        let window = self.window();
        for ((frame, cell), caption) in self.frames.iter().zip(&cells).zip(self.captions()) {
            let (drawing, text) = cell.split_vertically(self.cell_height);
            drawing
                .draw(&Rectangle::new(
                    [(4, 4), (self.cell_width as i32 - 4, self.cell_height as i32 - 2)],
                    RGBColor(200, 200, 200).stroke_width(1),
                ))
                .map_err(e)?;
            let w = frame.window.unwrap_or(window);
            let view = View::new(w, self.cell_width, self.cell_height, 12.0);
            for shape in frame.shapes.iter().flat_map(|s| clip_shape(s, w)) {
                draw_shape(&drawing, &view, &shape).map_err(e)?;
            }
            let style = TextStyle::from(("sans-serif", CAPTION).into_font()).pos(
                plotters::style::text_anchor::Pos::new(
                    plotters::style::text_anchor::HPos::Center,
                    plotters::style::text_anchor::VPos::Top,
                ),
            );
            for (i, line) in caption.iter().enumerate() {
                text.draw_text(
                    line,
                    &style,
                    (self.cell_width as i32 / 2, 4 + (i as u32 * LINE) as i32),
                )
                .map_err(e)?;
            }
        }
        Ok(())
    }
}

fn draw_shape<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    view: &View,
    shape: &Shape,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let px = |p: [f64; 2]| {
        let (x, y) = view.map(p);
        (x.round() as i32, y.round() as i32)
    };
    match shape {
        Shape::Poly { points, closed, paint } => {
            let mut pts: Vec<(i32, i32)> = points.iter().map(|&p| px(p)).collect();
            if let (Some(fill), true) = (paint.fill, *closed) {
                area.draw(&Polygon::new(pts.clone(), rgb(fill).filled()))?;
            }
            if *closed && let Some(&first) = pts.first() {
                pts.push(first);
            }
            area.draw(&PathElement::new(pts, rgb(paint.stroke).stroke_width(paint.width)))?;
        }
        Shape::Circle { center, radius, paint } => {
            let c = px(*center);
            let r = ((radius * view.scale).round() as i32).max(2);
            if let Some(fill) = paint.fill {
                area.draw(&plotters::element::Circle::new(c, r, rgb(fill).filled()))?;
            }
            area.draw(&plotters::element::Circle::new(
                c,
                r,
                rgb(paint.stroke).stroke_width(paint.width),
            ))?;
        }
    }
    Ok(())
}

fn hex(c: (u8, u8, u8)) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// An SVG that shows `frames` one after another in a loop (SMIL discrete visibility
/// keyframes), each for `frame_seconds`, with its first caption line under the drawing.
pub fn animated_svg(title: &str, frames: &[Frame], window: [f64; 4], frame_seconds: f64) -> String {
    let (w, h) = (480u32, 480u32);
    let total = frame_seconds * frames.len().max(1) as f64;
    let n = frames.len().max(1) as f64;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{}" viewBox="0 0 {w} {}" font-family="DejaVu Sans, sans-serif">"#,
        h + 70,
        h + 70
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="24" font-size="18" text-anchor="middle">{}</text>"#,
        w / 2,
        escape(title)
    );
    for (j, f) in frames.iter().enumerate() {
        let a = j as f64 / n;
        let b = (j + 1) as f64 / n;
        let (values, times) = if frames.len() == 1 {
            ("visible".to_owned(), "0".to_owned())
        } else if j == 0 {
            ("visible;hidden".to_owned(), format!("0;{b:.6}"))
        } else if j + 1 == frames.len() {
            ("hidden;visible".to_owned(), format!("0;{a:.6}"))
        } else {
            ("hidden;visible;hidden".to_owned(), format!("0;{a:.6};{b:.6}"))
        };
        let initial = if j == 0 { "visible" } else { "hidden" };
        let _ = writeln!(s, r#"<g visibility="{initial}" transform="translate(0,30)">"#);
        let _ = writeln!(
            s,
            r#"<animate attributeName="visibility" values="{values}" keyTimes="{times}" dur="{total:.4}s" calcMode="discrete" repeatCount="indefinite"/>"#
        );
        let fw = f.window.unwrap_or(window);
        let view = View::new(fw, w, h, 16.0);
        for shape in f.shapes.iter().flat_map(|s| clip_shape(s, fw)) {
            match &shape {
                Shape::Poly { points, closed, paint } => {
                    let pts: Vec<String> = points
                        .iter()
                        .map(|&p| {
                            let (x, y) = view.map(p);
                            format!("{x:.2},{y:.2}")
                        })
                        .collect();
                    let tag = if *closed { "polygon" } else { "polyline" };
                    let fill = paint.fill.filter(|_| *closed).map_or("none".to_owned(), hex);
                    let _ = writeln!(
                        s,
                        r#"<{tag} points="{}" fill="{fill}" stroke="{}" stroke-width="{}"/>"#,
                        pts.join(" "),
                        hex(paint.stroke),
                        paint.width
                    );
                }
                Shape::Circle { center, radius, paint } => {
                    let (x, y) = view.map(*center);
                    let r = (radius * view.scale).max(2.0);
                    let fill = paint.fill.map_or("none".to_owned(), hex);
                    let _ = writeln!(
                        s,
                        r#"<circle cx="{x:.2}" cy="{y:.2}" r="{r:.2}" fill="{fill}" stroke="{}" stroke-width="{}"/>"#,
                        hex(paint.stroke),
                        paint.width
                    );
                }
            }
        }
        for (i, line) in f.caption.iter().enumerate() {
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}" font-size="14" text-anchor="middle">{}</text>"#,
                w / 2,
                h + 8 + 16 * i as u32,
                escape(line)
            );
        }
        let _ = writeln!(s, "</g>");
    }
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(t: f64, x: f64) -> Frame {
        let paint = Paint { stroke: (0, 0, 0), width: 2, fill: Some((200, 200, 255)) };
        Frame {
            t,
            shapes: vec![
                Shape::Poly {
                    points: vec![[x, 0.0], [x + 1.0, 0.0], [x + 1.0, 1.0], [x, 1.0]],
                    closed: true,
                    paint,
                },
                Shape::Circle { center: [x + 0.5, 2.0], radius: 0.25, paint },
            ],
            caption: vec![format!("t = {t:.3} s"), "open".into()],
            window: None,
        }
    }

    #[test]
    fn clipping_cuts_polygons_lines_and_circles() {
        let paint = Paint { stroke: (0, 0, 0), width: 1, fill: None };
        let w = [0.0, 0.0, 1.0, 1.0];
        let square = Shape::Poly {
            points: vec![[-1.0, -1.0], [0.5, -1.0], [0.5, 0.5], [-1.0, 0.5]],
            closed: true,
            paint,
        };
        match &clip_shape(&square, w)[..] {
            [Shape::Poly { points, .. }] => {
                let area: f64 = (0..points.len())
                    .map(|i| {
                        let (a, b) = (points[i], points[(i + 1) % points.len()]);
                        a[0] * b[1] - b[0] * a[1]
                    })
                    .sum::<f64>()
                    / 2.0;
                assert!((area.abs() - 0.25).abs() < 1e-12, "{area}");
            }
            other => panic!("{other:?}"),
        }
        let line = Shape::Poly { points: vec![[-1.0, 0.5], [2.0, 0.5]], closed: false, paint };
        assert_eq!(
            clip_shape(&line, w),
            vec![Shape::Poly { points: vec![[0.0, 0.5], [1.0, 0.5]], closed: false, paint }]
        );
        let far = Shape::Circle { center: [3.0, 3.0], radius: 0.5, paint };
        assert!(clip_shape(&far, w).is_empty());
    }

    #[test]
    fn bounds_cover_all_frames() {
        let b = bounds(&[square(0.0, 0.0), square(1.0, 2.0)]);
        assert!(b[0] < 0.0 && b[2] > 3.0 && b[1] < 0.0 && b[3] > 2.25);
    }

    #[test]
    fn view_keeps_aspect_and_flips_y() {
        let v = View::new([0.0, 0.0, 2.0, 1.0], 200, 200, 0.0);
        assert_eq!(v.map([0.0, 1.0]), (0.0, 50.0));
        assert_eq!(v.map([2.0, 0.0]), (200.0, 150.0));
    }

    #[test]
    fn animation_has_one_keyframed_group_per_frame() {
        let frames: Vec<Frame> = (0..5).map(|k| square(k as f64 * 0.1, k as f64 * 0.2)).collect();
        let svg = animated_svg("test & check", &frames, bounds(&frames), 0.2);
        assert_eq!(svg.matches("<animate ").count(), 5);
        assert_eq!(svg.matches("<polygon").count(), 5);
        assert!(svg.contains(r#"dur="1.0000s""#));
        assert!(svg.contains("test &amp; check"));
        assert!(svg.contains(r#"values="hidden;visible;hidden" keyTimes="0;0.200000;0.400000""#));
    }

    #[test]
    fn strip_writes_svg_png_and_animation() -> Result<()> {
        let dir = tempfile::tempdir()?;
        let frames: Vec<Frame> = (0..3).map(|k| square(k as f64, k as f64 * 0.3)).collect();
        let strip = Strip {
            title: "Strip".into(),
            frames: frames.clone(),
            columns: 3,
            cell_width: 160,
            cell_height: 160,
            window: None,
        };
        let files = strip.write(dir.path(), "strip", &frames, 0.5)?;
        assert_eq!(files.len(), 3);
        for f in &files {
            assert!(std::fs::metadata(f)?.len() > 100, "{}", f.display());
        }
        let svg = std::fs::read_to_string(&files[0])?;
        assert!(svg.contains("t = 2.000 s"));
        Ok(())
    }
}
