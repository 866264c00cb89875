//! Drawing of the pictures of a run ([`super::Plotter`]): fonts, colours, panels of curves
//! over bands of the DOFs' states, and the PNG writer's rasterisation with plotters.

use super::*;

/// Registers the bundled font as plotters' `sans-serif` (once).
pub(super) fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // a font compiled into the crate and checked by the tests: it parses
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../../../assets/fonts/DejaVuSans-subset.ttf"),
        );
    });
}

// ---- drawing ----

pub(super) const FONT: &str = "sans-serif";
pub(super) const BACKGROUND: RGBColor = WHITE;
/// Curve colours (matplotlib's tab10).
pub(super) const C_BLUE: RGBColor = RGBColor(31, 119, 180);
pub(super) const C_ORANGE: RGBColor = RGBColor(255, 127, 14);
pub(super) const C_GREEN: RGBColor = RGBColor(44, 160, 44);
pub(super) const C_RED: RGBColor = RGBColor(214, 39, 40);
pub(super) const C_PURPLE: RGBColor = RGBColor(148, 103, 189);
pub(super) const C_BROWN: RGBColor = RGBColor(140, 86, 75);
pub(super) const C_GREY: RGBColor = RGBColor(127, 127, 127);
pub(super) const C_OLIVE: RGBColor = RGBColor(188, 189, 34);
pub(super) const C_BLACK: RGBColor = RGBColor(0, 0, 0);
/// Band colours.
pub(super) const B_STICK: RGBColor = RGBColor(214, 230, 245);
pub(super) const B_SLIP: RGBColor = RGBColor(253, 222, 194);
pub(super) const B_LOCKED: RGBColor = RGBColor(222, 214, 235);
pub(super) const B_STOP: RGBColor = RGBColor(247, 206, 206);

/// Colours of the three components (x, y, z) of the transmitted force and moment.
pub const COMPONENT_COLORS: [[u8; 3]; 3] = [rgb(C_BLUE), rgb(C_ORANGE), rgb(C_GREEN)];

pub(super) const fn rgb(c: RGBColor) -> [u8; 3] {
    [c.0, c.1, c.2]
}

/// A curve of a panel.
pub(super) struct Curve {
    pub(super) label: String,
    pub(super) color: RGBColor,
    pub(super) dashed: bool,
    pub(super) points: Vec<(f64, f64)>,
}

/// A band of a panel: the intervals where a state holds.
pub(super) struct Band {
    pub(super) label: &'static str,
    pub(super) color: RGBColor,
    pub(super) spans: Vec<(f64, f64)>,
}

/// An event line: time, colour, number (0: none).
pub(super) type Mark = (f64, RGBColor, usize);

/// One panel: title, curves over bands, horizontal lines (stops), event lines.
pub(super) struct Panel {
    pub(super) title: String,
    pub(super) curves: Vec<Curve>,
    pub(super) bands: Vec<Band>,
    /// `(value, label)`: dashed red lines (the stops).
    pub(super) levels: Vec<(f64, String)>,
    pub(super) marks: Vec<Mark>,
}

impl Panel {
    pub(super) fn new(title: impl Into<String>) -> Self {
        Panel {
            title: title.into(),
            curves: Vec::new(),
            bands: Vec::new(),
            levels: Vec::new(),
            marks: Vec::new(),
        }
    }

    pub(super) fn curve(
        &mut self,
        label: impl Into<String>,
        color: RGBColor,
        points: Vec<(f64, f64)>,
    ) {
        self.curves.push(Curve {
            label: label.into(),
            color,
            dashed: false,
            points,
        });
    }

    pub(super) fn band(&mut self, label: &'static str, color: RGBColor, spans: Vec<(f64, f64)>) {
        if !spans.is_empty() {
            self.bands.push(Band {
                label,
                color,
                spans,
            });
        }
    }

    /// The y range: the curves, the levels and 0 ([`y_range`]).
    pub(super) fn y(&self) -> (f64, f64) {
        let (lo, hi) = self
            .curves
            .iter()
            .flat_map(|c| c.points.iter().map(|p| p.1))
            .chain(self.levels.iter().map(|l| l.0))
            .filter(|v| v.is_finite())
            .fold((0.0f64, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
        y_range(lo, hi)
    }
}

pub(super) fn font(size: f64) -> TextStyle<'static> {
    (FONT, size).into_font().color(&C_BLACK)
}

/// Dispatches a drawing function on the backend of a root area.
pub(super) fn on_root(root: &Root<'_>, f: &mut dyn FnMut(&dyn AnyArea) -> Drawn) -> Drawn {
    match root {
        Root::Png(a) => f(a),
        Root::Svg(a) => f(a),
    }
}

/// What the drawing code needs of an area, object-safe over the two backends.
pub(super) trait AnyArea {
    /// Fills with the background.
    fn clear(&self) -> Drawn;
    /// Draws text at `pos` (area pixels).
    fn text(&self, s: &str, style: &TextStyle, pos: (i32, i32)) -> Drawn;
    /// Draws a panel in the rectangle `(x, y, w, h)` of the area.
    fn panel(&self, rect: (i32, i32, u32, u32), panel: &Panel, t: (f64, f64)) -> Drawn;
    /// Writes the file.
    fn present(&self) -> Drawn;
}

impl<DB: DrawingBackend> AnyArea for DrawingArea<DB, Shift>
where
    DB::ErrorType: 'static,
{
    fn clear(&self) -> Drawn {
        Ok(self.fill(&BACKGROUND)?)
    }
    fn text(&self, s: &str, style: &TextStyle, pos: (i32, i32)) -> Drawn {
        Ok(self.draw_text(s, style, pos)?)
    }
    fn panel(&self, (x, y, w, h): (i32, i32, u32, u32), panel: &Panel, t: (f64, f64)) -> Drawn {
        let (aw, ah) = self.dim_in_pixel();
        let area = self.clone().shrink((x, y), (w.min(aw), h.min(ah)));
        draw_panel(&area, panel, t)
    }
    fn present(&self) -> Drawn {
        Ok(DrawingArea::present(self)?)
    }
}

/// Height of a panel's caption (title and legend) \[px\].
pub(super) const CAPTION: u32 = 24;

/// Draws a panel into `area`.
pub(super) fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    p: &Panel,
    t: (f64, f64),
) -> Drawn
where
    DB::ErrorType: 'static,
{
    let (caption, body) = area.split_vertically(CAPTION);
    // title, then the legend: a swatch and a label per curve and band
    let title = font(15.0);
    caption.draw_text(&p.title, &title, (8, 5))?;
    let mut x = 16 + caption.estimate_text_size(&p.title, &title)?.0 as i32;
    let small = font(12.0);
    let entries = p
        .curves
        .iter()
        .map(|c| (c.label.as_str(), c.color, false))
        .chain(p.bands.iter().map(|b| (b.label, b.color, true)))
        .chain((!p.levels.is_empty()).then_some(("stops", C_RED, false)));
    for (label, color, band) in entries {
        if band {
            caption.draw(&Rectangle::new([(x, 6), (x + 14, 18)], color.filled()))?;
        } else {
            caption.draw(&Rectangle::new([(x, 10), (x + 14, 13)], color.filled()))?;
        }
        caption.draw_text(label, &small, (x + 18, 6))?;
        x += 30 + caption.estimate_text_size(label, &small)?.0 as i32;
    }
    let (lo, hi) = p.y();
    let mut chart = ChartBuilder::on(&body)
        .margin_right(16)
        .margin_top(4)
        .x_label_area_size(36)
        .y_label_area_size(72)
        .build_cartesian_2d(t.0..t.1, lo..hi)?;
    let y_label = |v: &f64| axis_label(*v, lo, hi);
    chart
        .configure_mesh()
        .y_label_formatter(&y_label)
        .x_desc("t [s]")
        .label_style(font(12.0))
        .axis_desc_style(font(12.0))
        .max_light_lines(1)
        .light_line_style(RGBColor(245, 245, 245))
        .bold_line_style(RGBColor(225, 225, 225))
        .draw()?;
    for b in &p.bands {
        chart.draw_series(
            b.spans
                .iter()
                .map(|(t0, t1)| Rectangle::new([(*t0, lo), (*t1, hi)], b.color.filled())),
        )?;
    }
    for (level, _) in &p.levels {
        chart.draw_series(DashedLineSeries::new(
            [(t.0, *level), (t.1, *level)],
            8,
            5,
            C_RED.stroke_width(1),
        ))?;
    }
    for (time, color, _) in &p.marks {
        chart.draw_series(std::iter::once(PathElement::new(
            [(*time, lo), (*time, hi)],
            color.stroke_width(1),
        )))?;
    }
    for c in &p.curves {
        if c.dashed {
            chart.draw_series(DashedLineSeries::new(
                c.points.iter().copied(),
                6,
                4,
                c.color.stroke_width(2),
            ))?;
        } else {
            chart.draw_series(LineSeries::new(
                c.points.iter().copied(),
                c.color.stroke_width(2),
            ))?;
        }
    }
    // the event numbers at the top of their lines
    for (time, color, n) in p.marks.iter().filter(|m| m.2 > 0) {
        let (px, py) = chart.backend_coord(&(*time, hi));
        let style = font(11.0).color(color);
        body.draw_text(
            &n.to_string(),
            &style,
            (
                px + 2 - body.get_base_pixel().0,
                py + 2 - body.get_base_pixel().1,
            ),
        )?;
    }
    Ok(())
}

/// Colours of the five parts of a DOF's force and of the five energies.
pub(super) const PART_COLORS: [RGBColor; 6] = [C_BLUE, C_ORANGE, C_GREEN, C_RED, C_PURPLE, C_OLIVE];

pub(super) fn event_color(e: &KjointEvent) -> RGBColor {
    match e.severity() {
        Severity::Info => C_PURPLE,
        Severity::Notice => C_OLIVE,
        Severity::Warning => C_RED,
    }
}

/// The rectangle of row `row`, column `col` of `cols` \[px\].
pub(super) fn cell(row: u32, col: u32, cols: u32) -> (i32, i32, u32, u32) {
    let w = WIDTH / cols;
    (
        (col * w) as i32,
        (TITLE_HEIGHT + row * ROW_HEIGHT) as i32,
        w,
        ROW_HEIGHT,
    )
}

pub(super) fn draw_joint(
    root: Root<'_>,
    p: &JointPlot,
    t: (f64, f64),
    events: &[&KjointEvent],
) -> Drawn {
    let tr = &p.track;
    let marks: Vec<Mark> = events.iter().map(|e| (e.time, event_color(e), 0)).collect();
    let mut panels: Vec<((i32, i32, u32, u32), Panel)> = Vec::new();
    for (col, (what, unit)) in [("force", "N"), ("moment", "N·m")].iter().enumerate() {
        let mut panel = Panel::new(format!("transmitted {what} [{unit}]"));
        for k in 0..3 {
            let i = 3 * col + k;
            let label = format!(
                "A{}{}",
                if col == 0 { "F" } else { "M" },
                ["X", "Y", "Z"][k]
            );
            panel.curve(label, [C_BLUE, C_ORANGE, C_GREEN][k], tr.points(i));
        }
        panel.marks = marks.clone();
        panels.push((cell(0, col as u32, 2), panel));
    }
    for (k, d) in p.free.iter().enumerate() {
        let c = p.dof_curve(k);
        let ((what, fu), qu) = (d.load(), d.unit());
        let mut force = Panel::new(format!("{} {what} by part [{fu}]", d.name()));
        force.band("locked", B_LOCKED, tr.intervals(k, |f| f & LOCKED != 0));
        force.band(
            "stick",
            B_STICK,
            tr.intervals(k, |f| f & (STICK | SLIP | LOCKED) == STICK),
        );
        force.band(
            "slip",
            B_SLIP,
            tr.intervals(k, |f| f & SLIP != 0 && f & LOCKED == 0),
        );
        for (j, part) in PARTS.iter().enumerate() {
            let (lo, hi) = tr.extent(c + j);
            if lo != 0.0 || hi != 0.0 {
                force.curve(*part, PART_COLORS[j], tr.points(c + j));
            }
        }
        force.curve("law total", C_BLACK, tr.points(c + 6));
        force.curves.push(Curve {
            label: "transmitted".into(),
            color: C_BROWN,
            dashed: true,
            points: tr.points(d.index()),
        });
        force.marks = marks.clone();
        panels.push((cell(1 + k as u32, 0, 2), force));

        let mut q = Panel::new(format!("{} [{qu}] and its stops", d.name()));
        q.band(
            "beyond a stop",
            B_STOP,
            tr.intervals(k, |f| f & AT_STOP != 0),
        );
        q.curve(d.name(), C_BLUE, tr.points(c + 7));
        let (smin, smax) = p.stops[k];
        for (v, name) in [(smin, "SD-"), (smax, "SD+")] {
            if v != 0.0 {
                q.levels.push((v, name.to_string()));
            }
        }
        q.marks = marks.clone();
        panels.push((cell(1 + k as u32, 1, 2), q));
    }
    let e = p.energy_curve();
    let mut en = Panel::new("energy of the joint [J]: stored, and dissipated so far");
    for (j, name) in ENERGIES.iter().enumerate() {
        let (lo, hi) = tr.extent(e + j);
        if j == 0 || lo != 0.0 || hi != 0.0 {
            let color = [C_BLUE, C_BROWN, C_ORANGE, C_GREEN, C_RED, C_GREY, C_OLIVE][j];
            en.curve(*name, color, tr.points(e + j));
        }
    }
    en.marks = marks;
    panels.push((cell(1 + p.free.len() as u32, 0, 1), en));

    let free: Vec<&str> = p.free.iter().map(|d| d.name()).collect();
    let title = format!(
        "joint `{}`: {} ({}), t = {} … {} s{}",
        p.name,
        p.joint_type.name(),
        if free.is_empty() {
            "no free DOF".to_string()
        } else {
            format!("free: {}", free.join(", "))
        },
        short(t.0),
        short(t.1),
        decimated(tr.width),
    );
    on_root(&root, &mut |a| {
        a.clear()?;
        a.text(&title, &font(18.0), (10, 10))?;
        for (rect, panel) in &panels {
            a.panel(*rect, panel, t)?;
        }
        a.present()
    })
}

pub(super) fn draw_balance(
    root: Root<'_>,
    tr: &Track,
    t: (f64, f64),
    events: &[KjointEvent],
    dropped: usize,
) -> Drawn {
    let marks: Vec<Mark> = events
        .iter()
        .enumerate()
        .map(|(i, e)| (e.time, event_color(e), i + 1))
        .collect();
    let mut top = Panel::new("energy of the model [J]");
    for (k, name, color) in [
        (K, "kinetic K", C_BLUE),
        (V, "potential V", C_ORANGE),
        (S, "stored S", C_GREEN),
        (D, "dissipated D", C_RED),
        (TOTAL, "K+V+S+D", C_BLACK),
    ] {
        top.curve(name, color, tr.points(k));
    }
    top.curves.push(Curve {
        label: "E₀ + W (initial + work of loads, motions and motors)".into(),
        color: C_PURPLE,
        dashed: true,
        points: tr.points(REFERENCE),
    });
    top.marks = marks.clone();
    let mut bottom = Panel::new("residual (K+V+S+D) − (E₀+W) [J]");
    bottom.curve("residual", C_BLACK, tr.points(RESIDUAL));
    bottom.marks = marks;

    let title = format!(
        "energy balance, t = {} … {} s{}",
        short(t.0),
        short(t.1),
        decimated(tr.width)
    );
    let mut lines: Vec<String> = events
        .iter()
        .enumerate()
        .take(EVENT_LINES)
        .map(|(i, e)| cut(&format!("{}  {e}", i + 1), 170))
        .collect();
    let more = events.len().saturating_sub(EVENT_LINES) + dropped;
    if events.is_empty() {
        lines.push("no events".into());
    } else if more > 0 {
        lines.push(format!("… and {more} more"));
    }
    on_root(&root, &mut |a| {
        a.clear()?;
        a.text(&title, &font(18.0), (10, 10))?;
        a.panel(cell(0, 0, 1), &top, t)?;
        a.panel(cell(1, 0, 1), &bottom, t)?;
        let y0 = (TITLE_HEIGHT + 2 * ROW_HEIGHT) as i32;
        a.text("events:", &font(13.0), (10, y0 + 2))?;
        for (i, l) in lines.iter().enumerate() {
            let y = y0 + ((i as u32 + 1) * EVENT_LINE_HEIGHT) as i32;
            let color = events.get(i).map_or(C_BLACK, event_color);
            a.text(l, &font(12.0).color(&color), (24, y))?;
        }
        a.present()
    })
}

/// A tick label of a y axis spanning `lo ..= hi`: as many decimals as a twentieth of the
/// span needs (ticks 0.0005 apart read `0.0005`, `0.0010`), in exponent notation when the
/// axis' largest magnitude is below 1e-3 or from 1e6 on (a moment of 1e-11 N·m reads
/// `1.0e-11`), `0` for zero. plotters' own labels read `0.0` and `-0.0` for every tick of
/// an axis spanning 1e-11, and `-0.0` above `0.0` on one spanning 3e-5.
pub fn axis_label(v: f64, lo: f64, hi: f64) -> String {
    let resolution = (hi - lo) / 20.0;
    if !v.is_finite() || !(resolution > 0.0) || !resolution.is_finite() {
        return format!("{v}");
    }
    if v.abs() <= resolution * 1e-6 {
        return "0".into();
    }
    let res_exp = resolution.log10().floor() as i32;
    let mag = lo.abs().max(hi.abs());
    if !(1e-3..1e6).contains(&mag) {
        let digits = (mag.log10().floor() as i32 - res_exp).clamp(0, 6) as usize;
        format!("{v:.digits$e}")
    } else {
        let decimals = (-res_exp).clamp(0, 9) as usize;
        format!("{v:.decimals$}")
    }
}

/// A time for a title: up to 6 significant digits.
pub(super) fn short(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s.is_empty() || s == "-" {
        "0".into()
    } else {
        s.to_string()
    }
}

/// The title's note on decimation.
pub(super) fn decimated(width: u64) -> String {
    if width > 1 {
        format!(" (each point the min and max of {width} records)")
    } else {
        String::new()
    }
}

/// `s` cut to `n` characters with an ellipsis.
pub(super) fn cut(s: &str, n: usize) -> String {
    if s.chars().count() <= n {
        s.to_string()
    } else {
        s.chars().take(n - 1).chain(std::iter::once('…')).collect()
    }
}
