//! A small software rasteriser for the pictures of the built-in examples, so
//! that they need nothing but cargo (no Python, no ParaView, no GPU).
//!
//! - [`Image`]: an RGB buffer with Gouraud-shaded triangles (a scalar is
//!   interpolated linearly across each triangle and mapped to a colour per
//!   pixel), 1-pixel lines blended over what is there, filled rectangles, text
//!   in an 8×8 bitmap font (ASCII, Latin-1 and Greek, scaled by whole
//!   numbers), and PNG output.
//! - [`viridis`]: the perceptually uniform colormap of matplotlib.
//! - [`Plot`] and [`Image::plot`]: a titled panel that fits 2D triangles with
//!   nodal values into a rectangle (equal scales on both axes), draws mesh
//!   edges over them and a colour bar with the minimum and maximum below;
//!   [`Plot::add_polygon`] and [`add_cut`] fill it from mesh faces and from a
//!   planar cut through a volume mesh.
//! - [`Chart`] and [`Image::chart`]: a titled x–y chart with ticked, labelled
//!   axes, curves, markers and a legend.
//!
//! Pixel (x, y) covers [x, x+1) × [y, y+1), y downwards; a triangle colours
//! the pixels whose centres it contains (closed edges: shared edges are drawn
//! by both sides, with equal values).

use font8x8::{UnicodeFonts, BASIC_FONTS, GREEK_FONTS, LATIN_FONTS};
use seam::VolumeMesh;
pub use seam_case::report::label;
use std::collections::BTreeSet;
use std::io::{self, Write};

/// An RGB colour.
pub type Rgb = [u8; 3];

/// An RGB picture, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    width: usize,
    height: usize,
    rgb: Vec<u8>,
}

/// A 2D point in pixels or in world units.
pub type P2 = [f64; 2];

impl Image {
    /// A `width × height` picture filled with `background`.
    pub fn new(width: usize, height: usize, background: Rgb) -> Image {
        Image { width, height, rgb: background.repeat(width * height) }
    }

    /// The colour of pixel (x, y).
    ///
    /// # Panics
    /// If (x, y) lies outside.
    #[cfg(test)]
    pub fn get(&self, x: usize, y: usize) -> Rgb {
        let i = 3 * (y * self.width + x);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Sets pixel (x, y) to `c` blended over it with opacity `alpha` ∈ [0, 1];
    /// pixels outside are ignored.
    pub fn blend(&mut self, x: i64, y: i64, c: Rgb, alpha: f64) {
        if x < 0 || y < 0 || x as usize >= self.width || y as usize >= self.height {
            return;
        }
        let i = 3 * (y as usize * self.width + x as usize);
        for k in 0..3 {
            let old = self.rgb[i + k] as f64;
            self.rgb[i + k] = (old + alpha * (c[k] as f64 - old)).round() as u8;
        }
    }

    /// Fills the triangle `p` (pixel coordinates), interpolating the nodal
    /// values `v` linearly and colouring each pixel by `color(value)`.
    /// Degenerate triangles draw nothing.
    pub fn triangle(&mut self, p: [P2; 3], v: [f64; 3], color: &impl Fn(f64) -> Rgb) {
        let area = cross(p[0], p[1], p[2]);
        if area.abs() < 1e-12 {
            return;
        }
        let lo = |k: usize| p.iter().map(|q| q[k]).fold(f64::INFINITY, f64::min);
        let hi = |k: usize| p.iter().map(|q| q[k]).fold(f64::NEG_INFINITY, f64::max);
        let (x0, x1) =
            ((lo(0) - 0.5).floor().max(0.0) as i64, (hi(0) - 0.5).ceil().min(self.width as f64 - 1.0) as i64);
        let (y0, y1) = (
            (lo(1) - 0.5).floor().max(0.0) as i64,
            (hi(1) - 0.5).ceil().min(self.height as f64 - 1.0) as i64,
        );
        let eps = -1e-9;
        for y in y0..=y1 {
            for x in x0..=x1 {
                let c = [x as f64 + 0.5, y as f64 + 0.5];
                let b =
                    [cross(p[1], p[2], c) / area, cross(p[2], p[0], c) / area, cross(p[0], p[1], c) / area];
                if b.iter().all(|&w| w >= eps) {
                    self.blend(x, y, color(b[0] * v[0] + b[1] * v[1] + b[2] * v[2]), 1.0);
                }
            }
        }
    }

    /// A 1-pixel line from `a` to `b` (pixel coordinates), blended with opacity
    /// `alpha`.
    pub fn line(&mut self, a: P2, b: P2, c: Rgb, alpha: f64) {
        let n = (b[0] - a[0]).abs().max((b[1] - a[1]).abs()).ceil().max(1.0) as usize;
        let mut last = (i64::MIN, i64::MIN);
        for i in 0..=n {
            let t = i as f64 / n as f64;
            let (x, y) =
                ((a[0] + t * (b[0] - a[0])).floor() as i64, (a[1] + t * (b[1] - a[1])).floor() as i64);
            if (x, y) != last {
                self.blend(x, y, c, alpha);
                last = (x, y);
            }
        }
    }

    /// Fills the rectangle of pixels [x, x+w) × [y, y+h).
    pub fn rect(&mut self, x: i64, y: i64, w: i64, h: i64, c: Rgb) {
        for j in y..y + h {
            for i in x..x + w {
                self.blend(i, j, c, 1.0);
            }
        }
    }

    /// Writes `text` with its top-left corner at (x, y), each font pixel
    /// `scale × scale` pixels (8·scale pixels per character). Characters the
    /// font lacks are drawn as '?'.
    pub fn text(&mut self, x: i64, y: i64, text: &str, scale: usize, c: Rgb) {
        let s = scale as i64;
        for (k, ch) in text.chars().enumerate() {
            let glyph = glyph(ch);
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..8 {
                    if bits & (1 << col) != 0 {
                        let (px, py) = (x + (8 * k as i64 + col) * s, y + row as i64 * s);
                        self.rect(px, py, s, s, c);
                    }
                }
            }
        }
    }

    /// Encodes the picture as an 8-bit RGB PNG.
    ///
    /// # Errors
    /// Any I/O error of `w`.
    pub fn write_png(&self, w: impl Write) -> io::Result<()> {
        let mut encoder = png::Encoder::new(w, self.width as u32, self.height as u32);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(io::Error::other)?;
        writer.write_image_data(&self.rgb).map_err(io::Error::other)?;
        writer.finish().map_err(io::Error::other)
    }

    /// The picture as PNG bytes ([`Image::write_png`]).
    ///
    /// # Errors
    /// Only if the encoder fails.
    pub fn png(&self) -> io::Result<Vec<u8>> {
        let mut bytes = Vec::new();
        self.write_png(&mut bytes)?;
        Ok(bytes)
    }
}

/// Twice the signed area of (a, b, c).
fn cross(a: P2, b: P2, c: P2) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The 8×8 bitmap of `ch` (rows top down, bit 0 leftmost).
fn glyph(ch: char) -> [u8; 8] {
    BASIC_FONTS
        .get(ch)
        .or_else(|| LATIN_FONTS.get(ch))
        .or_else(|| GREEK_FONTS.get(ch))
        .or_else(|| BASIC_FONTS.get('?'))
        .unwrap_or([0; 8])
}

/// Viridis at t ∈ [0, 1] (clamped), interpolated linearly between 17 samples
/// of matplotlib's table.
pub fn viridis(t: f64) -> Rgb {
    const TABLE: [Rgb; 17] = [
        [68, 1, 84],
        [72, 21, 104],
        [72, 38, 119],
        [69, 55, 129],
        [63, 71, 136],
        [57, 85, 140],
        [50, 100, 142],
        [45, 113, 142],
        [39, 127, 142],
        [34, 140, 141],
        [31, 154, 138],
        [37, 168, 131],
        [53, 183, 121],
        [80, 196, 106],
        [115, 208, 86],
        [154, 218, 60],
        [253, 231, 37],
    ];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let s = t * (TABLE.len() - 1) as f64;
    let i = (s.floor() as usize).min(TABLE.len() - 2);
    let f = s - i as f64;
    std::array::from_fn(|k| {
        (TABLE[i][k] as f64 + f * (TABLE[i + 1][k] as f64 - TABLE[i][k] as f64)).round() as u8
    })
}

/// One panel: triangles with nodal values and edges, in world coordinates
/// (x to the right, y upwards).
#[derive(Clone, Debug, Default)]
pub struct Plot {
    /// Title lines.
    pub title: Vec<String>,
    /// Triangles and their nodal values.
    pub triangles: Vec<([P2; 3], [f64; 3])>,
    /// Mesh edges drawn over the triangles.
    pub edges: Vec<(P2, P2)>,
    /// Thicker lines drawn last (e.g. an interface).
    pub lines: Vec<(P2, P2)>,
}

impl Plot {
    /// The range of the values (min, max); (0, 0) without triangles.
    pub fn range(&self) -> (f64, f64) {
        let values = self.triangles.iter().flat_map(|t| t.1).filter(|v| v.is_finite());
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
        if lo > hi {
            (0.0, 0.0)
        } else {
            (lo, hi)
        }
    }
}

impl Plot {
    /// Adds a face (a triangle or a polygon with nodal values) and its edges:
    /// a polygon as triangles around its centre, which carries the mean value
    /// (no diagonal stands out).
    pub fn add_polygon(&mut self, corners: &[P2], values: &[f64]) {
        if corners.len() == 3 {
            self.triangles.push(([corners[0], corners[1], corners[2]], [values[0], values[1], values[2]]));
        } else {
            let n = corners.len() as f64;
            let centre = [0, 1].map(|k| corners.iter().map(|c| c[k]).sum::<f64>() / n);
            let mean = values.iter().sum::<f64>() / n;
            for k in 0..corners.len() {
                let l = (k + 1) % corners.len();
                self.triangles.push(([corners[k], corners[l], centre], [values[k], values[l], mean]));
            }
        }
        for k in 0..corners.len() {
            self.edges.push((corners[k], corners[(k + 1) % corners.len()]));
        }
    }
}

/// The faces of `mesh`'s cells that lie in the plane x_`axis` = `at` (every
/// corner within `tol`), each once.
pub fn faces_in_plane(mesh: &VolumeMesh, axis: usize, at: f64, tol: f64) -> Vec<Vec<usize>> {
    let on = |p: usize| (mesh.points()[p][axis] - at).abs() <= tol;
    let mut seen = BTreeSet::new();
    let mut faces = Vec::new();
    for cell in mesh.cells() {
        for face in cell.faces() {
            if face.nodes().iter().all(|&p| on(p)) {
                let mut key = face.nodes().to_vec();
                key.sort_unstable();
                if seen.insert(key) {
                    // Second-order faces as their first-order pieces.
                    faces.extend(face.linear_pieces());
                }
            }
        }
    }
    faces
}

/// Adds the cut x_`axis` = `at` through `mesh` (the cell faces in that plane,
/// [`faces_in_plane`] to 1e-9) to `plot`, point p drawn at `place(p)` with the
/// value `value(p)`. Returns the number of faces added (0: the plane is no
/// grid plane of the mesh).
pub fn add_cut(
    plot: &mut Plot,
    mesh: &VolumeMesh,
    axis: usize,
    at: f64,
    place: impl Fn(usize) -> P2,
    value: impl Fn(usize) -> f64,
) -> usize {
    let faces = faces_in_plane(mesh, axis, at, 1e-9);
    for face in &faces {
        let corners: Vec<P2> = face.iter().map(|&p| place(p)).collect();
        let values: Vec<f64> = face.iter().map(|&p| value(p)).collect();
        plot.add_polygon(&corners, &values);
    }
    faces.len()
}

/// 1, 2 or 5 times a power of ten, the largest not above `x`.
pub fn nice_below(x: f64) -> f64 {
    let p = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0].into_iter().map(|m| m * p).find(|&v| v <= x).unwrap_or(p)
}

/// A magnification for a title: "50", "2000", "0.5".
pub fn label_factor(m: f64) -> String {
    if m >= 1.0 {
        format!("{m:.0}")
    } else {
        format!("{m}")
    }
}

/// Text colour and the edge colour of the panels.
const INK: Rgb = [20, 20, 20];

impl Image {
    /// Draws `plot` into the pixel rectangle (x, y, w, h): the title lines at
    /// the top (font scale 2, or 1 for a line too long for it), the triangles fitted below with equal scales,
    /// and a horizontal colour bar (viridis, min left, max right) with its
    /// labels at the bottom.
    pub fn plot(&mut self, x: i64, y: i64, w: i64, h: i64, plot: &Plot) {
        let line_height = 20;
        for (k, t) in plot.title.iter().enumerate() {
            let scale = if 16 * t.chars().count() as i64 + 20 <= w { 2 } else { 1 };
            self.text(x + 10, y + 6 + k as i64 * line_height, t, scale, INK);
        }
        let top = y + 14 + plot.title.len() as i64 * line_height;
        let bar_height = 16;
        let bottom = y + h - bar_height - 34;
        let (lo, hi) = plot.range();
        let scale = if hi > lo { 1.0 / (hi - lo) } else { 0.0 };
        let color = |v: f64| viridis((v - lo) * scale);
        // World bounding box of everything drawn.
        let points = plot
            .triangles
            .iter()
            .flat_map(|t| t.0)
            .chain(plot.edges.iter().chain(&plot.lines).flat_map(|e| [e.0, e.1]));
        let (mut a, mut b) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points {
            for k in 0..2 {
                a[k] = a[k].min(p[k]);
                b[k] = b[k].max(p[k]);
            }
        }
        if a[0] > b[0] {
            return;
        }
        let (aw, ah) = ((w - 20) as f64, (bottom - top) as f64);
        let s = (aw / (b[0] - a[0]).max(1e-300)).min(ah / (b[1] - a[1]).max(1e-300));
        let (ox, oy) =
            (x as f64 + 10.0 + 0.5 * (aw - s * (b[0] - a[0])), top as f64 + 0.5 * (ah + s * (b[1] - a[1])));
        let to_pixel = |p: P2| [ox + s * (p[0] - a[0]), oy - s * (p[1] - a[1])];
        for (t, v) in &plot.triangles {
            self.triangle(t.map(to_pixel), *v, &color);
        }
        for (p, q) in &plot.edges {
            self.line(to_pixel(*p), to_pixel(*q), INK, 0.45);
        }
        for (p, q) in &plot.lines {
            let (p, q) = (to_pixel(*p), to_pixel(*q));
            for d in [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]] {
                self.line([p[0] + d[0], p[1] + d[1]], [q[0] + d[0], q[1] + d[1]], INK, 1.0);
            }
        }
        // The colour bar.
        let (bx, bw, by) = (x + 40, w - 80, y + h - bar_height - 30);
        for i in 0..bw {
            let c = viridis(i as f64 / (bw - 1).max(1) as f64);
            self.rect(bx + i, by, 1, bar_height, c);
        }
        let (min, max) = (label(lo), label(hi));
        self.text(bx, by + bar_height + 6, &min, 2, INK);
        self.text(bx + bw - 16 * max.chars().count() as i64, by + bar_height + 6, &max, 2, INK);
    }
}

/// A named series of points of a [`Chart`].
#[derive(Clone, Debug)]
pub struct Series {
    /// The legend's text.
    pub label: String,
    /// Its colour.
    pub color: Rgb,
    /// The points, in world units.
    pub points: Vec<P2>,
}

/// An x–y chart: curves (polylines, 2 pixels wide) and markers (discs) over
/// ticked axes, with a legend in the upper right corner of the plot area.
#[derive(Clone, Debug, Default)]
pub struct Chart {
    /// Title lines.
    pub title: Vec<String>,
    /// The x axis: its label and range.
    pub x: (String, f64, f64),
    /// The y axis: its label and range.
    pub y: (String, f64, f64),
    /// Polylines.
    pub curves: Vec<Series>,
    /// Points drawn as discs.
    pub markers: Vec<Series>,
}

/// Tick values on [lo, hi]: multiples of a step of 1, 2 or 5 times a power of
/// ten giving at most `n` intervals.
pub fn ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return vec![lo];
    }
    // The smallest step m · 10^e (m = 1, 2, 5) not below (hi − lo)/n; tick k
    // is k·m · 10^e, computed in one rounding (0.6, not 3 × 0.2).
    let wanted = (hi - lo) / n.max(1) as f64;
    let mut e = wanted.log10().floor() as i32;
    let scaled = |k: f64, e: i32| if e >= 0 { k * 10f64.powi(e) } else { k / 10f64.powi(-e) };
    let m = match [1.0, 2.0, 5.0].into_iter().find(|&m| scaled(m, e) >= wanted * (1.0 - 1e-9)) {
        Some(m) => m,
        None => {
            e += 1;
            1.0
        }
    };
    let step = scaled(m, e);
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).map(|k| scaled(k as f64 * m, e)).collect()
}

impl Image {
    /// A filled disc of radius `r` pixels centred at `c`.
    pub fn disc(&mut self, c: P2, r: f64, color: Rgb) {
        let (x0, x1) = ((c[0] - r).floor() as i64, (c[0] + r).ceil() as i64);
        let (y0, y1) = ((c[1] - r).floor() as i64, (c[1] + r).ceil() as i64);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (dx, dy) = (x as f64 + 0.5 - c[0], y as f64 + 0.5 - c[1]);
                if dx * dx + dy * dy <= r * r {
                    self.blend(x, y, color, 1.0);
                }
            }
        }
    }

    /// Draws `chart` into the pixel rectangle (x, y, w, h): the title lines at
    /// the top (font scale 2), the axes with ticks and their labels (scale 2),
    /// the curves and markers clipped to the axes' ranges, and the legend.
    pub fn chart(&mut self, x: i64, y: i64, w: i64, h: i64, chart: &Chart) {
        for (k, t) in chart.title.iter().enumerate() {
            let scale = if 16 * t.chars().count() as i64 + 20 <= w { 2 } else { 1 };
            self.text(x + 10, y + 6 + k as i64 * 20, t, scale, INK);
        }
        let (x_ticks, y_ticks) = (ticks(chart.x.1, chart.x.2, 10), ticks(chart.y.1, chart.y.2, 6));
        let widest = y_ticks.iter().map(|&v| label(v).chars().count()).max().unwrap_or(1) as i64;
        // The plot area: left of it the y tick labels and the y axis label
        // (written above the axis), below it the x tick labels and the x label.
        let left = x + 30 + 16 * widest;
        let top = y + 24 + 20 * chart.title.len() as i64 + 20;
        let (right, bottom) = (x + w - 30, y + h - 70);
        let (sx, sy) = (
            (right - left) as f64 / (chart.x.2 - chart.x.1).max(1e-300),
            (bottom - top) as f64 / (chart.y.2 - chart.y.1).max(1e-300),
        );
        let to_pixel =
            |p: P2| [left as f64 + sx * (p[0] - chart.x.1), bottom as f64 - sy * (p[1] - chart.y.1)];
        let grey = [225, 225, 225];
        for &v in &x_ticks {
            let px = to_pixel([v, chart.y.1])[0];
            self.line([px, top as f64], [px, bottom as f64], grey, 1.0);
            let text = label(v);
            let half = 8 * text.chars().count() as i64;
            self.text(px.round() as i64 - half, bottom + 10, &text, 2, INK);
        }
        for &v in &y_ticks {
            let py = to_pixel([chart.x.1, v])[1];
            self.line([left as f64, py], [right as f64, py], grey, 1.0);
            let text = label(v);
            self.text(left - 10 - 16 * text.chars().count() as i64, py.round() as i64 - 8, &text, 2, INK);
        }
        self.rect(left, top, 2, bottom - top + 2, INK);
        self.rect(left, bottom, right - left, 2, INK);
        let x_label = &chart.x.0;
        self.text((left + right) / 2 - 8 * x_label.chars().count() as i64, bottom + 36, x_label, 2, INK);
        self.text(x + 10, top - 28, &chart.y.0, 2, INK);
        let inside =
            |p: P2| (chart.x.1..=chart.x.2).contains(&p[0]) && (chart.y.1..=chart.y.2).contains(&p[1]);
        for s in &chart.curves {
            for pair in s.points.windows(2) {
                if inside(pair[0]) && inside(pair[1]) {
                    let (a, b) = (to_pixel(pair[0]), to_pixel(pair[1]));
                    for d in [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]] {
                        self.line([a[0] + d[0], a[1] + d[1]], [b[0] + d[0], b[1] + d[1]], s.color, 1.0);
                    }
                }
            }
        }
        // Each series of markers smaller than the one before, so that
        // coinciding points stay visible.
        let radius = |k: usize| (7.5 - 2.5 * k as f64).max(2.5);
        for (k, s) in chart.markers.iter().enumerate() {
            for &p in s.points.iter().filter(|&&p| inside(p)) {
                self.disc(to_pixel(p), radius(k) + 1.5, INK);
                self.disc(to_pixel(p), radius(k), s.color);
            }
        }
        // The legend.
        let entries = chart
            .curves
            .iter()
            .map(|s| (s, None))
            .chain(chart.markers.iter().enumerate().map(|(k, s)| (s, Some(k))));
        let longest = entries.clone().map(|(s, _)| s.label.chars().count()).max().unwrap_or(0) as i64;
        let (lx, mut ly) = (right - 60 - 16 * longest, top + 14);
        for (s, marker) in entries {
            let centre = [lx as f64 + 20.0, ly as f64 + 8.0];
            match marker {
                None => self.rect(lx, ly + 7, 40, 3, s.color),
                Some(k) => {
                    self.disc(centre, radius(k) + 1.5, INK);
                    self.disc(centre, radius(k), s.color);
                }
            }
            self.text(lx + 50, ly, &s.label, 2, INK);
            ly += 26;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_triangle_covers_the_pixels_inside_with_interpolated_colours() {
        let mut image = Image::new(40, 30, [255, 255, 255]);
        // Value 0 at the left corners, 1 at the right one: colour varies with x only.
        image.triangle([[0.0, 0.0], [40.0, 15.0], [0.0, 30.0]], [0.0, 1.0, 0.0], &viridis);
        assert_eq!(image.get(0, 15), viridis(0.5 / 40.0));
        assert_eq!(image.get(20, 15), viridis(20.5 / 40.0));
        assert_eq!(image.get(38, 15), viridis(38.5 / 40.0));
        // Outside: above the upper edge near the right, and the corners.
        assert_eq!(image.get(30, 2), [255, 255, 255]);
        assert_eq!(image.get(39, 0), [255, 255, 255]);
        assert_eq!(image.get(39, 29), [255, 255, 255]);
        // The pixel count is the area, up to the edge pixels.
        let inside =
            (0..30).flat_map(|y| (0..40).map(move |x| (x, y))).filter(|&(x, y)| image.get(x, y) != [255; 3]);
        let n = inside.count() as f64;
        assert!((n - 600.0).abs() < 40.0, "{n} pixels for an area of 600");
    }

    #[test]
    fn two_triangles_of_a_square_leave_no_gap() {
        let mut image = Image::new(20, 20, [255, 255, 255]);
        let black = |_: f64| [0, 0, 0];
        let (a, b, c, d) = ([2.3, 2.7], [17.6, 3.1], [16.9, 18.2], [2.1, 17.4]);
        image.triangle([a, b, c], [0.0; 3], &black);
        image.triangle([a, c, d], [0.0; 3], &black);
        for y in 5..15 {
            for x in 5..15 {
                assert_eq!(image.get(x, y), [0, 0, 0], "pixel ({x}, {y})");
            }
        }
    }

    #[test]
    fn lines_text_and_png() {
        let mut image = Image::new(30, 12, [255, 255, 255]);
        image.line([0.5, 0.5], [29.5, 0.5], [0, 0, 0], 1.0);
        assert!((0..30).all(|x| image.get(x, 0) == [0, 0, 0]));
        assert_eq!(image.get(5, 1), [255, 255, 255]);
        image.line([0.5, 5.5], [10.5, 5.5], [0, 0, 0], 0.5);
        assert_eq!(image.get(3, 5), [128, 128, 128]);
        image.text(0, 2, "I", 1, [0, 0, 0]);
        let ink =
            (2..10).flat_map(|y| (0..8).map(move |x| (x, y))).filter(|&(x, y)| image.get(x, y) == [0, 0, 0]);
        assert!(ink.count() > 6, "the glyph is drawn");
        let mut bytes = Vec::new();
        image.write_png(&mut bytes).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        assert_eq!(glyph('ν'), GREEK_FONTS.get('ν').unwrap());
    }

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(ticks(0.0, 1.0, 6), vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
        assert_eq!(ticks(0.0, 1.6, 8), vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6]);
        assert_eq!(ticks(-3.0, 12.0, 4), vec![0.0, 5.0, 10.0]);
        assert_eq!(ticks(1.0, 1.0, 4), vec![1.0]);
        assert_eq!(ticks(0.0, 2.0, 8), vec![0.0, 0.5, 1.0, 1.5, 2.0]);
        assert_eq!(ticks(0.0, 1.2, 6), vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.2]);
    }

    #[test]
    fn a_chart_draws_its_curves_and_markers_where_they_belong() {
        let mut image = Image::new(400, 300, [255, 255, 255]);
        let red = [200, 0, 0];
        let chart = Chart {
            title: vec!["t".into()],
            x: ("x".into(), 0.0, 1.0),
            y: ("y".into(), 0.0, 1.0),
            curves: vec![Series { label: "c".into(), color: red, points: vec![[0.0, 0.0], [1.0, 1.0]] }],
            markers: vec![Series { label: "m".into(), color: [0, 0, 200], points: vec![[1.0, 0.0]] }],
        };
        image.chart(0, 0, 400, 300, &chart);
        let all = (0..300).flat_map(|y| (0..400).map(move |x| (x, y)));
        let count = |c: Rgb| all.clone().filter(|&(x, y)| image.get(x, y) == c).count();
        assert!(count(red) > 200, "the diagonal is drawn");
        // The marker sits in the lower right corner of the plot area.
        let blue: Vec<(usize, usize)> =
            all.clone().filter(|&(x, y)| image.get(x, y) == [0, 0, 200]).collect();
        assert!(blue.iter().any(|&(x, y)| x > 300 && y > 200), "{blue:?}");
    }

    #[test]
    fn viridis_ends_and_labels() {
        assert_eq!(viridis(0.0), [68, 1, 84]);
        assert_eq!(viridis(1.0), [253, 231, 37]);
        assert_eq!(viridis(f64::NAN), [68, 1, 84]);
        assert_eq!(label(-1.25), "-1.25");
        assert_eq!(label(0.0012345), "1.234e-3");
        assert_eq!(label(0.0), "0");
    }

    #[test]
    fn a_plot_fills_its_panel_and_its_colour_bar() {
        let mut image = Image::new(300, 300, [255, 255, 255]);
        let plot = Plot {
            title: vec!["t".into()],
            triangles: vec![([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [0.0, 1.0, 2.0])],
            edges: vec![([0.0, 0.0], [1.0, 1.0])],
            lines: vec![],
        };
        assert_eq!(plot.range(), (0.0, 2.0));
        image.plot(0, 0, 300, 300, &plot);
        // The colour bar runs from viridis(0) to viridis(1).
        let by = 300 - 16 - 30 + 8;
        assert_eq!(image.get(40, by), viridis(0.0));
        assert_eq!(image.get(300 - 41, by), viridis(1.0));
        // The triangle is fitted into x ∈ [42, 258], y ∈ [34, 250] (the square
        // area below the title and above the bar): its lower-right corner is
        // coloured, the upper-left one is not.
        assert_ne!(image.get(250, 240), [255, 255, 255]);
        assert_eq!(image.get(50, 42), [255, 255, 255]);
    }
}
