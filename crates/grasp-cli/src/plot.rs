//! A self-contained SVG plot of force histories (normal force solid, friction dashed per
//! finger), like thesis figures 15 and 17. Written by hand: a few lines of SVG need no
//! plotting library or system fonts.

use std::fmt::Write as _;

use grasp_transfer::StepRecord;

const COLORS: [&str; 8] = [
    "#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
];

/// What the plot needs of a run, gathered step by step: the first and last step times and,
/// per step with forces, every finger's normal and friction force (2 numbers per finger and
/// step).
pub struct ForceHistory {
    names: Vec<String>,
    span: Option<(f64, f64)>,
    /// `(time s, [P, |Q|] per finger in scene order)` of every step with forces.
    points: Vec<(f64, Vec<[f64; 2]>)>,
}

impl ForceHistory {
    /// An empty history of these fingers.
    pub fn new(names: &[String]) -> Self {
        ForceHistory {
            names: names.to_vec(),
            span: None,
            points: Vec::new(),
        }
    }

    /// Adds a step.
    pub fn push(&mut self, r: &StepRecord) {
        let t0 = self.span.map_or(r.time_s, |s| s.0);
        self.span = Some((t0, r.time_s));
        if !r.solution.status.has_forces() {
            return;
        }
        let forces = self
            .names
            .iter()
            .map(|n| {
                r.solution
                    .finger(n)
                    .map_or([0.0, 0.0], |f| [f.normal_force_n, f.tangential_magnitude_n])
            })
            .collect();
        self.points.push((r.time_s, forces));
    }

    /// The SVG document (see [`force_history_svg`]).
    pub fn svg(&self, title: &str) -> String {
        force_history_svg(self, title)
    }
}

/// Returns an SVG document plotting every finger's normal and friction force against time.
fn force_history_svg(hist: &ForceHistory, title: &str) -> String {
    let names = &hist.names;
    let (w, h, ml, mr, mt, mb) = (900.0, 500.0, 70.0, 190.0, 40.0, 50.0);
    let t0 = hist.span.map_or(0.0, |s| s.0);
    let t1 = hist.span.map_or(1.0, |s| s.1).max(t0 + 1e-9);
    let fmax = hist
        .points
        .iter()
        .flat_map(|p| p.1.iter().flatten())
        .fold(0.0_f64, |m, x| m.max(*x))
        .max(1e-9);
    let ytop = nice_ceiling(fmax);
    let x = |t: f64| ml + (t - t0) / (t1 - t0) * (w - ml - mr);
    let y = |f: f64| h - mb - f / ytop * (h - mt - mb);
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">
<rect width="{w}" height="{h}" fill="white"/>
<text x="{}" y="22" text-anchor="middle" font-size="14">Forces during the hand-off: {}</text>
"#,
        (ml + w - mr) / 2.0,
        escape(title)
    );
    // Axes and ticks.
    let _ = writeln!(
        s,
        r##"<line x1="{ml}" y1="{}" x2="{}" y2="{}" stroke="#000"/>"##,
        h - mb,
        w - mr,
        h - mb
    );
    let _ = writeln!(
        s,
        r##"<line x1="{ml}" y1="{mt}" x2="{ml}" y2="{}" stroke="#000"/>"##,
        h - mb
    );
    for i in 0..=5 {
        let f = ytop * i as f64 / 5.0;
        let _ = writeln!(
            s,
            r##"<line x1="{ml}" y1="{0}" x2="{1}" y2="{0}" stroke="#ddd"/><text x="{2}" y="{3}" text-anchor="end">{4}</text>"##,
            y(f),
            w - mr,
            ml - 6.0,
            y(f) + 4.0,
            fmt(f)
        );
    }
    // At most a dozen ticks, counted by integers (adding dt to a large t may not change it).
    let dt = nice_ceiling((t1 - t0) / 6.0);
    let first = (t0 / dt).ceil();
    for i in 0..12 {
        let t = (first + i as f64) * dt;
        if t > t1 + 1e-9 * dt {
            break;
        }
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
            x(t),
            h - mb + 18.0,
            fmt(t)
        );
    }
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">time [s]</text>"#,
        (ml + w - mr) / 2.0,
        h - 10.0
    );
    let _ = writeln!(
        s,
        r#"<text x="18" y="{}" text-anchor="middle" transform="rotate(-90 18 {})">force [N]</text>"#,
        (mt + h - mb) / 2.0,
        (mt + h - mb) / 2.0
    );
    for (i, name) in names.iter().enumerate() {
        let c = COLORS[i % COLORS.len()];
        for (dash, pick) in [("", 0usize), (r#" stroke-dasharray="6 4""#, 1usize)] {
            let pts: Vec<String> = hist
                .points
                .iter()
                .map(|(t, f)| format!("{:.2},{:.2}", x(*t), y(f[i][pick])))
                .collect();
            let _ = writeln!(
                s,
                r#"<polyline fill="none" stroke="{c}" stroke-width="1.8"{dash} points="{}"/>"#,
                pts.join(" ")
            );
        }
        let ly = mt + 20.0 + 36.0 * i as f64;
        let lx = w - mr + 15.0;
        let _ = writeln!(
            s,
            r#"<line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="{c}" stroke-width="2"/><text x="{}" y="{}">{} normal P</text><line x1="{lx}" y1="{}" x2="{}" y2="{}" stroke="{c}" stroke-width="2" stroke-dasharray="6 4"/><text x="{}" y="{}">{} friction |Q|</text>"#,
            lx + 25.0,
            lx + 30.0,
            ly + 4.0,
            escape(name),
            ly + 16.0,
            lx + 25.0,
            ly + 16.0,
            lx + 30.0,
            ly + 20.0,
            escape(name)
        );
    }
    s.push_str("</svg>\n");
    s
}

fn nice_ceiling(v: f64) -> f64 {
    let e = 10f64.powf(v.log10().floor());
    for m in [1.0, 2.0, 2.5, 5.0, 10.0] {
        if m * e >= v {
            return m * e;
        }
    }
    10.0 * e
}

fn fmt(v: f64) -> String {
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
