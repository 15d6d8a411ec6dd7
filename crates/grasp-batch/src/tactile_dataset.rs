//! A batch's tactile dataset (`grasp batch --npz`, `grasp sweep --npz`): one NumPy `.npz`
//! archive with, per grasp whose scene has a sensor and whose solve found forces, its sensor
//! arrays and its labels, keyed by the grasp's position in the input (`g<index>/`, eight
//! digits, as the result lines' `index`):
//!
//! - the arrays of `grasp solve --npz` under `g<index>/<finger>/taxels/...`, `.../markers/...`
//!   and `.../gel/...` (`grasp_io::NpzArchive::add_sensors`; with the sensor's response, the
//!   noise of read-out `index`);
//! - per finger the labels `g<index>/<finger>/normal_force_n` `()`,
//!   `.../tangential_force_n` `(3,)` (world frame, N), `.../friction_utilization` `()` (`|Q| /
//!   (mu P)`: 1 where the finger slides) and `.../stick_fraction` `()` (stick over stick and
//!   slip elements; NaN for a frictionless finger or one out of contact);
//! - `grasps` int64 `(G,)`: the indices written, in order.
//!
//! The line's `id` and `status` are in the result lines under the same `index`. A shard's
//! archive holds its own grasps; the keys never collide across shards, so the archives of a
//! job array read together as one (`{**np.load(a), **np.load(b)}`).

use std::io::{Seek, Write};

use grasp_io::NpzArchive;

use crate::result_line::ResultLine;

/// The dataset being written.
pub struct TactileDataset<W: Write + Seek> {
    archive: NpzArchive<W>,
    grasps: Vec<i64>,
}

impl<W: Write + Seek> TactileDataset<W> {
    /// A dataset written to `w`.
    pub fn new(w: W) -> Self {
        TactileDataset {
            archive: NpzArchive::new(w),
            grasps: Vec::new(),
        }
    }

    /// Adds `line`'s grasp, when it has readings (the module's arrays).
    pub fn add(&mut self, line: &ResultLine) -> std::io::Result<()> {
        if line.readings.is_empty() {
            return Ok(());
        }
        let prefix = format!("g{:08}/", line.index);
        self.archive.add_sensors(&prefix, &line.readings)?;
        for f in &line.fingers {
            let p = format!("{prefix}{}/", f.name);
            let a = &mut self.archive;
            a.array::<f64>(&format!("{p}normal_force_n"), &[], [f.normal_force_n])?;
            a.array::<f64>(
                &format!("{p}tangential_force_n"),
                &[3],
                f.tangential_force_n,
            )?;
            let u = f.friction_utilization;
            a.array::<f64>(&format!("{p}friction_utilization"), &[], [u])?;
            let stick = f.stick_fraction.unwrap_or(f64::NAN);
            a.array::<f64>(&format!("{p}stick_fraction"), &[], [stick])?;
        }
        self.grasps.push(line.index as i64);
        Ok(())
    }

    /// Writes `grasps` and completes the archive.
    pub fn finish(mut self) -> std::io::Result<W> {
        let n = self.grasps.len() as u64;
        self.archive.array::<i64>("grasps", &[n], self.grasps)?;
        self.archive.finish()
    }
}
