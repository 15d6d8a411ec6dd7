//! The tactile readings of a hand-off, step by step (`Transfer.sensor_history`): per finger
//! with a sensor and per kind, one flat array `(T, nx, ny, 3)` (a gel image: its heights
//! `(T, nx, ny)` and its colours `(T, nx, ny, 3)`), NaN at the steps where the finger has no
//! readings (released, or a step without forces).

use grasp_model::{Scene, SensorReadings};

/// One finger's readings over the steps.
#[derive(Debug)]
pub struct SensorHistory {
    /// The finger.
    pub finger: String,
    /// Taxels `[nx, ny]` and their forces `[normal, t1, t2]`, N, `(T, nx, ny, 3)`.
    pub taxels: Option<([usize; 2], Vec<f64>)>,
    /// Markers `[nx, ny]` and their displacements `[normal, t1, t2]`, m, `(T, nx, ny, 3)`.
    pub markers: Option<([usize; 2], Vec<f64>)>,
    /// A gel image's pixels `[nx, ny]`, heights (m, `(T, nx, ny)`) and colours (`(T, nx, ny,
    /// 3)`).
    pub gel: Option<([usize; 2], Vec<f64>, Vec<f64>)>,
}

/// Every sensor finger's history, scene order.
#[derive(Debug, Default)]
pub struct SensorHistories(pub Vec<SensorHistory>);

impl SensorHistories {
    /// Empty histories of the sensors of `scene`.
    pub fn of(scene: &Scene) -> SensorHistories {
        let fingers = scene.fingers.iter().filter_map(|f| {
            let s = f.sensor.as_ref()?;
            Some(SensorHistory {
                finger: f.name.clone(),
                taxels: s.taxels.as_ref().map(|t| (t.count, Vec::new())),
                markers: s.markers.as_ref().map(|m| (m.count, Vec::new())),
                gel: s.gel.as_ref().map(|g| (g.image_px, Vec::new(), Vec::new())),
            })
        });
        SensorHistories(fingers.collect())
    }

    /// Appends one step's readings `sensors` (NaN for a finger without).
    pub fn push(&mut self, sensors: &[SensorReadings]) {
        for h in &mut self.0 {
            let r = sensors.iter().find(|s| s.finger == h.finger);
            if let Some((count, values)) = h.taxels.as_mut() {
                let read = r
                    .and_then(|r| r.taxels.as_ref())
                    .map(|t| t.force_n.as_slice());
                extend(values, *count, read);
            }
            if let Some((count, values)) = h.markers.as_mut() {
                let read = r.and_then(|r| r.markers.as_ref());
                extend(values, *count, read.map(|m| m.displacement_m.as_slice()));
            }
            if let Some(([nx, ny], heights, colours)) = h.gel.as_mut() {
                let read = r.and_then(|r| r.gel.as_ref());
                match read {
                    Some(g) => heights.extend(&g.height_m),
                    None => heights.extend(std::iter::repeat_n(f64::NAN, *nx * *ny)),
                }
                extend(colours, [*nx, *ny], read.map(|g| g.rgb.as_slice()));
            }
        }
    }

    /// Bytes one step adds for the sensors of `scene`.
    pub fn bytes_per_step(scene: &Scene) -> u64 {
        let cells = |c: [usize; 2]| (c[0] * c[1] * 3 * 8) as u64;
        let of = |s: &grasp_model::SensorSpec| {
            s.taxels.as_ref().map_or(0, |t| cells(t.count))
                + s.markers.as_ref().map_or(0, |m| cells(m.count))
                + s.gel.as_ref().map_or(0, |g| cells(g.image_px) * 4 / 3)
        };
        scene
            .fingers
            .iter()
            .filter_map(|f| f.sensor.as_ref())
            .map(of)
            .sum()
    }
}

/// `read`'s rows appended to `values`, or a grid of NaN.
fn extend(values: &mut Vec<f64>, count: [usize; 2], read: Option<&[[f64; 3]]>) {
    match read {
        Some(rows) => values.extend(rows.iter().flatten()),
        None => values.extend(std::iter::repeat_n(f64::NAN, count[0] * count[1] * 3)),
    }
}
