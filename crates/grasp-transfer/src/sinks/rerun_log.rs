//! Rerun sink: a saved `.rrd` recording to replay a hand-off in the Rerun viewer.
//!
//! Entities (world frame, metres):
//! - `world/object` (static): a wireframe box around the contacts and the centre of mass;
//! - `world/fingers/<name>` (static): each finger as an arrow pointing at its contact;
//! - `world/forces/<name>/normal`, `.../friction`: force arrows on the object at the centre
//!   of pressure, scaled by `arrow_m_per_n`;
//! - `world/patches/<name>/pressure`: elements coloured by pressure (dark blue to yellow,
//!   relative to the step's largest pressure);
//! - `world/patches/<name>/state`: elements coloured by state (stick green, slip orange,
//!   separated grey);
//! - `plots/normal_force/<name>`, `plots/friction/<name>`: time series in newtons.
//!
//! Timelines: `schedule_time` (s) and `step`. Log time is disabled and the recording id is
//! fixed, so the same inputs give the same file.

use std::path::Path;

use grasp_model::ElementState;
use rerun::{Arrows3D, Boxes3D, Color, Points3D, RecordingStream, Scalars, SeriesLines};

use super::{sink_err, RunInfo, Sink};
use crate::error::TransferError;
use crate::stepper::StepRecord;

/// Writes a Rerun recording.
pub struct RerunSink {
    rec: Option<RecordingStream>,
    arrow_m_per_n: f32,
}

fn v3(v: &nalgebra::Vector3<f64>) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// A perceptually ordered colour ramp (dark blue, teal, yellow) for `u in [0, 1]`.
fn ramp(u: f64) -> Color {
    let u = u.clamp(0.0, 1.0);
    let stops = [
        (40.0, 30.0, 100.0),
        (30.0, 150.0, 140.0),
        (250.0, 230.0, 40.0),
    ];
    let (a, b, s) = if u < 0.5 {
        (stops[0], stops[1], u * 2.0)
    } else {
        (stops[1], stops[2], u * 2.0 - 1.0)
    };
    let mix = |x: f64, y: f64| (x + (y - x) * s).round() as u8;
    Color::from_rgb(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

impl RerunSink {
    /// Creates the recording file (the caller has checked it may be written).
    pub fn create(path: &Path) -> Result<Self, TransferError> {
        let rec = rerun::RecordingStreamBuilder::new("grasp")
            .recording_id("grasp-transfer")
            .save(path)
            .map_err(|e| sink_err("rerun", format!("{}: {e}", path.display())))?;
        rec.set_log_time_enabled(false);
        Ok(RerunSink {
            rec: Some(rec),
            arrow_m_per_n: 1.0,
        })
    }

    fn rec(&self) -> Result<&RecordingStream, TransferError> {
        self.rec
            .as_ref()
            .ok_or_else(|| sink_err("rerun", "already finished"))
    }
}

impl Sink for RerunSink {
    fn begin(&mut self, run: &RunInfo) -> Result<(), TransferError> {
        let g = run.geometry;
        let mut lo = g.center_of_mass_m;
        let mut hi = g.center_of_mass_m;
        for f in &g.fingers {
            lo = lo.inf(&f.frame.origin_m);
            hi = hi.sup(&f.frame.origin_m);
        }
        let size = (hi - lo).norm().max(1e-3);
        self.arrow_m_per_n = (0.3 * size / g.scales.load_n) as f32;
        let rec = self.rec()?;
        let err = |e: rerun::RecordingStreamError| sink_err("rerun", e);
        let centre = (lo + hi) * 0.5;
        let half = ((hi - lo) * 0.5).map(|x| x.max(0.02 * size));
        rec.log_static(
            "world/object",
            &Boxes3D::from_centers_and_half_sizes([v3(&centre)], [v3(&half)]),
        )
        .map_err(err)?;
        rec.log_static(
            "world/object/center_of_mass",
            &Points3D::new([v3(&g.center_of_mass_m)])
                .with_radii([0.01 * size as f32])
                .with_labels(["centre of mass"]),
        )
        .map_err(err)?;
        for f in &g.fingers {
            let len = 0.25 * size;
            let base = f.frame.origin_m - f.frame.normal * len;
            rec.log_static(
                format!("world/fingers/{}", f.name),
                &Arrows3D::from_vectors([v3(&(f.frame.normal * (0.9 * len)))])
                    .with_origins([v3(&base)])
                    .with_colors([Color::from_rgb(150, 150, 160)])
                    .with_labels([f.name.as_str()]),
            )
            .map_err(err)?;
            rec.log_static(
                format!("plots/normal_force/{}", f.name),
                &SeriesLines::new().with_names([format!("{} normal force [N]", f.name)]),
            )
            .map_err(err)?;
            rec.log_static(
                format!("plots/friction/{}", f.name),
                &SeriesLines::new().with_names([format!("{} friction force [N]", f.name)]),
            )
            .map_err(err)?;
        }
        Ok(())
    }

    fn step(&mut self, run: &RunInfo, r: &StepRecord) -> Result<(), TransferError> {
        let scale = self.arrow_m_per_n as f64;
        let rec = self.rec()?;
        let err = |e: rerun::RecordingStreamError| sink_err("rerun", e);
        rec.set_duration_secs("schedule_time", r.time_s);
        rec.set_time_sequence("step", r.index as i64);
        let p_max = r
            .solution
            .fingers
            .iter()
            .map(|f| f.peak_pressure_pa)
            .fold(0.0_f64, f64::max)
            .max(f64::MIN_POSITIVE);
        for fm in &run.geometry.fingers {
            let name = &fm.name;
            let Some(f) = r.solution.finger(name) else {
                // Released (or failed step): clear its arrows and patch, plot zero.
                let none: [[f32; 3]; 0] = [];
                for part in ["normal", "friction"] {
                    rec.log(
                        format!("world/forces/{name}/{part}"),
                        &Arrows3D::from_vectors(none),
                    )
                    .map_err(err)?;
                }
                for part in ["pressure", "state"] {
                    rec.log(format!("world/patches/{name}/{part}"), &Points3D::new(none))
                        .map_err(err)?;
                }
                rec.log(format!("plots/normal_force/{name}"), &Scalars::new([0.0]))
                    .map_err(err)?;
                rec.log(format!("plots/friction/{name}"), &Scalars::new([0.0]))
                    .map_err(err)?;
                continue;
            };
            let cop = nalgebra::Vector3::from(f.center_of_pressure_m);
            let pn = fm.frame.normal * (f.normal_force_n * scale);
            rec.log(
                format!("world/forces/{name}/normal"),
                &Arrows3D::from_vectors([v3(&pn)])
                    .with_origins([v3(&(cop - pn))])
                    .with_colors([Color::from_rgb(220, 60, 60)]),
            )
            .map_err(err)?;
            let q = nalgebra::Vector3::from(f.tangential_force_n) * scale;
            rec.log(
                format!("world/forces/{name}/friction"),
                &Arrows3D::from_vectors([v3(&q)])
                    .with_origins([v3(&cop)])
                    .with_colors([Color::from_rgb(60, 120, 230)]),
            )
            .map_err(err)?;
            let h = 0.5 * fm.patch.grid.hx.min(fm.patch.grid.hy);
            let pos: Vec<[f32; 3]> = f
                .elements
                .iter()
                .map(|e| e.position_m.map(|x| x as f32))
                .collect();
            rec.log(
                format!("world/patches/{name}/pressure"),
                &Points3D::new(pos.clone())
                    .with_colors(f.elements.iter().map(|e| ramp(e.pressure_pa / p_max)))
                    .with_radii(std::iter::repeat_n(0.9 * h as f32, pos.len())),
            )
            .map_err(err)?;
            let off = fm.frame.normal * (-2.0 * h);
            let pos_state: Vec<[f32; 3]> = f
                .elements
                .iter()
                .map(|e| v3(&(nalgebra::Vector3::from(e.position_m) + off)))
                .collect();
            rec.log(
                format!("world/patches/{name}/state"),
                &Points3D::new(pos_state)
                    .with_colors(f.elements.iter().map(|e| match e.state {
                        ElementState::Stick => Color::from_rgb(60, 180, 75),
                        ElementState::Slip => Color::from_rgb(245, 130, 48),
                        ElementState::Separated => Color::from_rgb(128, 128, 128),
                    }))
                    .with_radii(std::iter::repeat_n(0.6 * h as f32, f.elements.len())),
            )
            .map_err(err)?;
            rec.log(
                format!("plots/normal_force/{name}"),
                &Scalars::new([f.normal_force_n]),
            )
            .map_err(err)?;
            rec.log(
                format!("plots/friction/{name}"),
                &Scalars::new([f.tangential_magnitude_n]),
            )
            .map_err(err)?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), TransferError> {
        if let Some(rec) = self.rec.take() {
            rec.flush_blocking().map_err(|e| sink_err("rerun", e))?;
            drop(rec);
        }
        Ok(())
    }
}
