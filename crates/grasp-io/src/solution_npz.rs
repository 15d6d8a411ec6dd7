//! Solutions as NumPy `.npz` archives (`grasp solve --npz`, `grasp transfer --npz`): one
//! array per element field and finger, named `<finger>/<field>` (a prefix before it for a
//! transfer's steps: `step_00012/<finger>/<field>`), each a `.npy` entry of a zip archive stored
//! uncompressed as NumPy's `savez` writes it (`numpy.load(path)["f1/pressure_pa"]`).
//!
//! The fields are those of a solution's JSON elements under the same names, in element order
//! (`k = i ny + j`): `index` int64 `(N, 2)`; `local_m`, `tangential_force_n`, `traction_pa`,
//! `slip_m`, `step_slip_m` float64 `(N, 2)`; `position_m` float64 `(N, 3)`; `normal_force_n`,
//! `pressure_pa`, `gap_m` float64 `(N,)`; `state` uint8 `(N,)`, the code of each element's
//! state, whose name is `state_names[code]` (the archive's one array without a finger:
//! `["stick", "slip", "separated", "off_surface", "frictionless"]`, unicode);
//! `viscous_displacement_m` float64 `(N, 3)` on a viscoelastic contact. Beside them `grid`,
//! int64 `(2,)`: the patch's `[nx, ny]` (a field reshaped to `(nx, ny)` is the patch's map,
//! rows along `t1`). A finger's taxel sensor, when the scene has one, adds
//! `<finger>/taxels/force_n` float64 `(nx, ny, 3)` (normal, `t1`, `t2`, N),
//! `<finger>/taxels/centre_m` float64 `(nx, ny, 2)` and `<finger>/taxels/depth_m` float64 `()`;
//! its markers `<finger>/markers/displacement_m` float64 `(nx, ny, 3)` (normal, positive into
//! the pad, `t1`, `t2`, m) and `<finger>/markers/position_m` float64 `(nx, ny, 2)`; its gel
//! image `<finger>/gel/height_m` float64 `(nx, ny)` (m, positive into the pad),
//! `<finger>/gel/normal` float64 `(nx, ny, 3)` (`u`, `v`, `w` toward the camera),
//! `<finger>/gel/rgb` float64 `(nx, ny, 3)` (in `[0, 1]`) and `<finger>/gel/rgb8` uint8
//! `(nx, ny, 3)` ([`NpzArchive::add_sensors`]). A finger on a mount adds
//! `<finger>/core_translation_m` and `<finger>/core_rotation_rad` float64 `(3,)` (its core's
//! displacement, world frame); a hand `<hand>/force_n`, `<hand>/moment_nm`,
//! `<hand>/translation_m` and `<hand>/rotation_rad` float64 `(3,)`; a servo `<servo>/force_n`
//! and `<servo>/travel_m` float64 `()`. Every float is the solution's own float64, bit for bit. The archive is
//! the same for the same solution (entries dated 1980-01-01, the zip format's zero).

use std::io::{BufWriter, Seek, Write};

use grasp_model::{ElementSolution, ElementState, SensorReadings, Solution};

use crate::error::OutputError;
use crate::output_file::PendingOutput;
use npyz::WriterBuilder;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

/// Entries of more bytes than this are written with the zip format's 64-bit sizes.
const ZIP64_ABOVE_BYTES: u64 = u32::MAX as u64 / 2;

/// The element states by their code in the `state` arrays.
const STATE_NAMES: [ElementState; 5] = [
    ElementState::Stick,
    ElementState::Slip,
    ElementState::Separated,
    ElementState::OffSurface,
    ElementState::Frictionless,
];

/// Widest state name (`"frictionless"`), the unicode width of `state_names`.
const STATE_WIDTH: usize = 12;

/// The code of `state` in the `state` arrays: its place in [`STATE_NAMES`].
fn state_code(state: ElementState) -> u8 {
    STATE_NAMES.iter().position(|s| *s == state).unwrap_or(0) as u8
}

/// The patch's grid `[nx, ny]` of `elements` (element `k = i ny + j` at index `(i, j)`): one
/// more than the largest index along each direction, `[0, 0]` without elements.
fn grid_shape(elements: &[ElementSolution]) -> [i64; 2] {
    let most = |d: usize| elements.iter().map(|e| e.index[d] as i64 + 1).max();
    [most(0).unwrap_or(0), most(1).unwrap_or(0)]
}

/// Bytes of an array's data written to the archive at a time.
const BUFFER_BYTES: usize = 1 << 16;

/// The `.npy` header (magic, version, the dictionary of dtype, order and `shape`) of an array
/// of `T` in NumPy's default little-endian type, as npyz writes it: its writer writes the
/// header when it begins, and dropped before any value, writes nothing more (an unfinished
/// writer's drop reports nothing).
fn npy_header<T: npyz::AutoSerialize>(shape: &[u64]) -> std::io::Result<Vec<u8>> {
    let mut header = Vec::new();
    let writer = npyz::WriteOptions::<T>::new()
        .default_dtype()
        .shape(shape)
        .writer(&mut header)
        .begin_nd()?;
    drop(writer);
    Ok(header)
}

/// An `.npz` archive being written into `W`.
pub struct NpzArchive<W: Write + Seek> {
    zip: ZipWriter<W>,
    /// The `state_names` array is written (once, before the first solution's arrays).
    has_state_names: bool,
}

impl<W: Write + Seek> NpzArchive<W> {
    /// A new, empty archive written into `w`.
    pub fn new(w: W) -> Self {
        NpzArchive {
            zip: ZipWriter::new(w),
            has_state_names: false,
        }
    }

    /// Adds every finger's element fields of `solution`, named `<prefix><finger>/<field>`.
    pub fn add_solution(&mut self, prefix: &str, solution: &Solution) -> std::io::Result<()> {
        if !self.has_state_names {
            self.state_names("state_names")?;
            self.has_state_names = true;
        }
        for f in &solution.fingers {
            let p = format!("{prefix}{}/", f.name);
            let e = f.elements.as_slice();
            self.entries::<i64, 2>(&format!("{p}index"), e, |e, out| {
                e.index
                    .iter()
                    .for_each(|&i| out.extend_from_slice(&(i as i64).to_le_bytes()))
            })?;
            self.floats(&format!("{p}local_m"), e, |e| e.local_m)?;
            self.floats(&format!("{p}position_m"), e, |e| e.position_m)?;
            self.floats(&format!("{p}normal_force_n"), e, |e| [e.normal_force_n])?;
            self.floats(&format!("{p}tangential_force_n"), e, |e| {
                e.tangential_force_n
            })?;
            self.floats(&format!("{p}pressure_pa"), e, |e| [e.pressure_pa])?;
            self.floats(&format!("{p}traction_pa"), e, |e| e.traction_pa)?;
            self.floats(&format!("{p}gap_m"), e, |e| [e.gap_m])?;
            self.floats(&format!("{p}slip_m"), e, |e| e.slip_m)?;
            self.floats(&format!("{p}step_slip_m"), e, |e| e.step_slip_m)?;
            self.entries::<u8, 1>(&format!("{p}state"), e, |e, out| {
                out.push(state_code(e.state))
            })?;
            self.array::<i64>(&format!("{p}grid"), &[2], grid_shape(e))?;
            if e.iter().any(|e| e.viscous_displacement_m.is_some()) {
                self.floats(&format!("{p}viscous_displacement_m"), e, |e| {
                    e.viscous_displacement_m.unwrap_or([f64::NAN; 3])
                })?;
            }
            if let Some(core) = &f.mount_displacement {
                self.array(&format!("{p}core_translation_m"), &[3], core.translation_m)?;
                self.array(&format!("{p}core_rotation_rad"), &[3], core.rotation_rad)?;
            }
        }
        self.add_shared_springs(prefix, solution)
    }

    /// Adds each hand's and servo's arrays, named `<prefix><name>/<field>` (their names are
    /// none of the fingers'): a hand's `force_n`, `moment_nm`, `translation_m` and
    /// `rotation_rad` `(3,)`; a servo's `force_n` and `travel_m` `()`.
    fn add_shared_springs(&mut self, prefix: &str, solution: &Solution) -> std::io::Result<()> {
        for h in &solution.hands {
            let p = format!("{prefix}{}/", h.name);
            self.array(&format!("{p}force_n"), &[3], h.force_n)?;
            self.array(&format!("{p}moment_nm"), &[3], h.moment_nm)?;
            self.array(&format!("{p}translation_m"), &[3], h.translation_m)?;
            self.array(&format!("{p}rotation_rad"), &[3], h.rotation_rad)?;
        }
        for v in &solution.servos {
            let p = format!("{prefix}{}/", v.name);
            self.array(&format!("{p}force_n"), &[], [v.force_n])?;
            self.array(&format!("{p}travel_m"), &[], [v.travel_m])?;
        }
        Ok(())
    }

    /// Adds each finger's sensor readings: its taxels' as `<prefix><finger>/taxels/<field>`,
    /// `force_n` `(nx, ny, 3)`, `centre_m` `(nx, ny, 2)`, `depth_m` `()`; its markers' as
    /// `<prefix><finger>/markers/<field>`, `displacement_m` `(nx, ny, 3)`, `position_m`
    /// `(nx, ny, 2)`; its gel image's as `<prefix><finger>/gel/<field>`, `height_m` `(nx,
    /// ny)`, `normal` and `rgb` `(nx, ny, 3)`, `rgb8` uint8 `(nx, ny, 3)`.
    pub fn add_sensors(&mut self, prefix: &str, sensors: &[SensorReadings]) -> std::io::Result<()> {
        for s in sensors {
            if let Some(r) = &s.taxels {
                let p = format!("{prefix}{}/taxels/", s.finger);
                let [nx, ny] = r.count.map(|c| c as u64);
                let forces = r.force_n.iter().flat_map(|f| f.iter().copied());
                self.array::<f64>(&format!("{p}force_n"), &[nx, ny, 3], forces)?;
                let centres = r.centre_m.iter().flat_map(|c| c.iter().copied());
                self.array::<f64>(&format!("{p}centre_m"), &[nx, ny, 2], centres)?;
                self.array::<f64>(&format!("{p}depth_m"), &[], [r.depth_m])?;
            }
            if let Some(m) = &s.markers {
                let p = format!("{prefix}{}/markers/", s.finger);
                let [nx, ny] = m.count.map(|c| c as u64);
                let moved = m.displacement_m.iter().flat_map(|u| u.iter().copied());
                self.array::<f64>(&format!("{p}displacement_m"), &[nx, ny, 3], moved)?;
                let points = m.position_m.iter().flat_map(|c| c.iter().copied());
                self.array::<f64>(&format!("{p}position_m"), &[nx, ny, 2], points)?;
            }
            if let Some(g) = &s.gel {
                let p = format!("{prefix}{}/gel/", s.finger);
                let [nx, ny] = g.count.map(|c| c as u64);
                let heights = g.height_m.iter().copied();
                self.array::<f64>(&format!("{p}height_m"), &[nx, ny], heights)?;
                let normals = g.normal.iter().flat_map(|n| n.iter().copied());
                self.array::<f64>(&format!("{p}normal"), &[nx, ny, 3], normals)?;
                let colours = g.rgb.iter().flat_map(|c| c.iter().copied());
                self.array::<f64>(&format!("{p}rgb"), &[nx, ny, 3], colours)?;
                self.array::<u8>(&format!("{p}rgb8"), &[nx, ny, 3], g.rgb8())?;
            }
        }
        Ok(())
    }

    /// Adds a float64 array `name` of shape `(N,)` (one value an element) or `(N, C)`.
    fn floats<const C: usize>(
        &mut self,
        name: &str,
        elements: &[ElementSolution],
        field: impl Fn(&ElementSolution) -> [f64; C],
    ) -> std::io::Result<()> {
        self.entries::<f64, C>(name, elements, |e, out| {
            field(e)
                .iter()
                .for_each(|v| out.extend_from_slice(&v.to_le_bytes()))
        })
    }

    /// Adds an array `name` of `C` values of `T` per element (shape `(N,)` for one, `(N, C)`
    /// otherwise), `put` appending an element's little-endian bytes: NumPy's header from
    /// npyz, then the data a buffer at a time (not a write per value).
    fn entries<T: npyz::AutoSerialize, const C: usize>(
        &mut self,
        name: &str,
        elements: &[ElementSolution],
        put: impl Fn(&ElementSolution, &mut Vec<u8>),
    ) -> std::io::Result<()> {
        let n = elements.len() as u64;
        let shape: &[u64] = if C == 1 { &[n] } else { &[n, C as u64] };
        let value = std::mem::size_of::<T>();
        self.start(name, n * (C * value) as u64)?;
        self.zip.write_all(&npy_header::<T>(shape)?)?;
        let mut bytes = Vec::with_capacity(BUFFER_BYTES);
        for chunk in elements.chunks((BUFFER_BYTES / (C * value)).max(1)) {
            bytes.clear();
            chunk.iter().for_each(|e| put(e, &mut bytes));
            self.zip.write_all(&bytes)?;
        }
        Ok(())
    }

    /// Adds an array `name` of `shape` holding `values` (row-major), of `T`'s NumPy type.
    pub fn array<T: npyz::AutoSerialize>(
        &mut self,
        name: &str,
        shape: &[u64],
        values: impl IntoIterator<Item = T>,
    ) -> std::io::Result<()> {
        let bytes = shape.iter().product::<u64>() * std::mem::size_of::<T>() as u64;
        self.start(name, bytes)?;
        // The array and its header in one buffer, at most 1 MiB (a small array allocates
        // little: a dataset writes several a grasp).
        let capacity = (bytes as usize).saturating_add(256).min(1 << 20);
        let mut buffered = BufWriter::with_capacity(capacity, &mut self.zip);
        let mut w = npyz::WriteOptions::<T>::new()
            .default_dtype()
            .shape(shape)
            .writer(&mut buffered)
            .begin_nd()?;
        w.extend(values)?;
        w.finish()?;
        buffered.flush()
    }

    /// Adds the names of the state codes as a unicode array `name`.
    fn state_names(&mut self, name: &str) -> std::io::Result<()> {
        self.start(name, (STATE_NAMES.len() * 4 * STATE_WIDTH) as u64)?;
        let dtype = npyz::DType::Plain(
            format!("<U{STATE_WIDTH}")
                .parse()
                .expect("a valid unicode type string"),
        );
        let mut w = npyz::WriteOptions::<str>::new()
            .dtype(dtype)
            .shape(&[STATE_NAMES.len() as u64])
            .writer(&mut self.zip)
            .begin_nd()?;
        for s in STATE_NAMES {
            w.push(s.as_str())?;
        }
        w.finish()
    }

    /// Starts the entry of array `name`, of about `bytes` bytes of data.
    fn start(&mut self, name: &str, bytes: u64) -> std::io::Result<()> {
        let options = SimpleFileOptions::default()
            .compression_method(CompressionMethod::Stored)
            .last_modified_time(DateTime::default())
            .unix_permissions(0o644)
            .large_file(bytes > ZIP64_ABOVE_BYTES);
        self.zip
            .start_file(npyz::npz::file_name_from_array_name(name), options)?;
        Ok(())
    }

    /// Completes the archive (its central directory) and hands back the writer.
    pub fn finish(self) -> std::io::Result<W> {
        Ok(self.zip.finish()?)
    }
}

/// Writes the element fields of `solution` and the readings of its `sensors` (none for a
/// scene without sensors) as an archive into the temporary file of `pending` (the caller
/// commits it), naming its target on failure.
pub fn write_solution_npz(
    pending: &PendingOutput,
    solution: &Solution,
    sensors: &[SensorReadings],
) -> Result<(), OutputError> {
    let io = |e: std::io::Error| OutputError::io(pending.target(), "write", &e);
    let mut archive = NpzArchive::new(BufWriter::new(pending.file_handle()?));
    archive.add_solution("", solution).map_err(io)?;
    archive.add_sensors("", sensors).map_err(io)?;
    archive.finish().map_err(io)?.flush().map_err(io)
}
