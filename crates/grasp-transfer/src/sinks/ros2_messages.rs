//! The ROS 2 messages the MCAP's ROS 2 profile writes, as Rust types whose fields are the
//! messages' fields in their order ([`super::ros2_definitions`] has the definitions), and
//! their CDR encoding ([`cdr_message`]): little-endian CDR by the `cdr-encoding` crate (the
//! encoder of RustDDS) after the 4-byte encapsulation header that every ROS 2 serialized
//! message starts with (`00 01 00 00`: plain CDR, little-endian), as `ros2 bag record`
//! stores them.

use serde::{Serialize, Serializer};

/// The frame of finger `name`'s contact (`<name>/contact`): origin the contact point, x, y and
/// z along `t1`, `t2` and the inward normal.
pub fn contact_frame_id(name: &str) -> String {
    format!("{name}/contact")
}

/// The object's frame: its centre of mass, with the world's axes at the reference pose.
pub const OBJECT_FRAME: &str = "object";

/// `builtin_interfaces/msg/Time` (and `Duration`: the same fields).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Time {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds, `0 <= nanosec < 1e9`.
    pub nanosec: u32,
}

impl Time {
    /// The time `ns` nanoseconds after the epoch; `None` past what `Time` holds (its seconds
    /// are an `int32`: 2038-01-19).
    pub fn from_ns(ns: u64) -> Option<Self> {
        let sec = i32::try_from(ns / 1_000_000_000).ok()?;
        Some(Time {
            sec,
            nanosec: (ns % 1_000_000_000) as u32,
        })
    }

    /// Zero (a marker's lifetime of zero: forever).
    pub const ZERO: Time = Time { sec: 0, nanosec: 0 };
}

/// `std_msgs/msg/Header`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Header {
    /// When.
    pub stamp: Time,
    /// In which frame.
    pub frame_id: String,
}

/// `geometry_msgs/msg/Vector3` (and `Point`: the same fields).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Vector3 {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

impl From<nalgebra::Vector3<f64>> for Vector3 {
    fn from(v: nalgebra::Vector3<f64>) -> Self {
        Vector3 {
            x: v.x,
            y: v.y,
            z: v.z,
        }
    }
}

/// `geometry_msgs/msg/Quaternion`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}

impl From<nalgebra::UnitQuaternion<f64>> for Quaternion {
    fn from(q: nalgebra::UnitQuaternion<f64>) -> Self {
        Quaternion {
            x: q.i,
            y: q.j,
            z: q.k,
            w: q.w,
        }
    }
}

/// `geometry_msgs/msg/Pose` (and `Transform`: a translation and a rotation).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Pose {
    /// Position (a `Transform`'s translation), m.
    pub position: Vector3,
    /// Orientation (a `Transform`'s rotation).
    pub orientation: Quaternion,
}

/// `geometry_msgs/msg/WrenchStamped` (its `Wrench` inline: two vectors in a row).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WrenchStamped {
    /// Stamp and frame.
    pub header: Header,
    /// Force, N.
    pub force: Vector3,
    /// Moment about the frame's origin, N m.
    pub torque: Vector3,
}

/// `geometry_msgs/msg/TransformStamped`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransformStamped {
    /// Stamp and parent frame.
    pub header: Header,
    /// The frame this transform places.
    pub child_frame_id: String,
    /// The child frame's origin and axes in the parent frame.
    pub transform: Pose,
}

/// `tf2_msgs/msg/TFMessage`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TfMessage {
    /// The transforms.
    pub transforms: Vec<TransformStamped>,
}

/// Bytes serialized as a CDR `uint8[]` in one write.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Bytes(pub Vec<u8>);

impl Serialize for Bytes {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_bytes(&self.0)
    }
}

/// `sensor_msgs/msg/Image`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Image {
    /// Stamp and frame.
    pub header: Header,
    /// Rows.
    pub height: u32,
    /// Columns.
    pub width: u32,
    /// Pixel encoding (`32FC1`, `mono8`, `rgb8`, ...).
    pub encoding: String,
    /// 0: little-endian pixels.
    pub is_bigendian: u8,
    /// Bytes per row.
    pub step: u32,
    /// The pixels, row after row.
    pub data: Bytes,
}

/// `std_msgs/msg/ColorRGBA`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ColorRgba {
    /// Red, 0 to 1.
    pub r: f32,
    /// Green.
    pub g: f32,
    /// Blue.
    pub b: f32,
    /// Opacity.
    pub a: f32,
}

/// `visualization_msgs/msg/Marker` (the texture, UV coordinates and mesh file empty).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Marker {
    /// Stamp and frame.
    pub header: Header,
    /// Namespace.
    pub ns: String,
    /// Id in the namespace.
    pub id: i32,
    /// `ARROW` 0, `CUBE` 1, `SPHERE` 2, `CYLINDER` 3, `SPHERE_LIST` 7, `TRIANGLE_LIST` 11.
    pub r#type: i32,
    /// `ADD` 0, `DELETE` 2.
    pub action: i32,
    /// Pose.
    pub pose: Pose,
    /// Scale, m.
    pub scale: Vector3,
    /// Colour.
    pub color: ColorRgba,
    /// Lifetime (zero: forever).
    pub lifetime: Time,
    /// Moves with its frame.
    pub frame_locked: bool,
    /// Points (arrows: tail and head; lists: the items).
    pub points: Vec<Vector3>,
    /// Per-point colours (empty: `color`).
    pub colors: Vec<ColorRgba>,
    /// Unused: empty.
    pub texture_resource: String,
    /// Unused: an empty `sensor_msgs/CompressedImage`.
    pub texture: CompressedImage,
    /// Unused: empty.
    pub uv_coordinates: Vec<[f32; 2]>,
    /// Unused: empty.
    pub text: String,
    /// Unused: empty.
    pub mesh_resource: String,
    /// Unused: an empty `visualization_msgs/MeshFile`.
    pub mesh_file: MeshFile,
    /// Unused: false.
    pub mesh_use_embedded_materials: bool,
}

/// `visualization_msgs/msg/MeshFile`.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct MeshFile {
    /// The file's name.
    pub filename: String,
    /// Its bytes.
    pub data: Bytes,
}

/// `sensor_msgs/msg/CompressedImage`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompressedImage {
    /// Stamp and frame.
    pub header: Header,
    /// Format.
    pub format: String,
    /// Bytes.
    pub data: Bytes,
}

/// `visualization_msgs/msg/MarkerArray`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MarkerArray {
    /// The markers.
    pub markers: Vec<Marker>,
}

/// `grasp_msgs/msg/FingerState` (`ros2/grasp_msgs/msg/FingerState.msg`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FingerState {
    /// Name.
    pub name: String,
    /// `held`, `load`, `approach` or `released`.
    pub control: String,
    /// N.
    pub commanded_load_n: f64,
    /// m.
    pub commanded_approach_m: f64,
    /// N.
    pub normal_force_n: f64,
    /// N.
    pub friction_force_n: f64,
    /// N m.
    pub torsional_moment_nm: f64,
    /// `|Q| / (mu P)`.
    pub friction_utilization: f64,
    /// `1 - |Q| / (mu P)`; NaN for a frictionless finger or one not in the grasp.
    pub slip_margin: f64,
    /// Counted in the step's smallest slip margin.
    pub slip_margin_counted: bool,
    /// A mounted finger's core displacement, world frame, m (NaN without).
    pub core_displacement_m: [f64; 3],
    /// Of the elements in contact.
    pub stick_fraction: f64,
    /// Of the elements in contact.
    pub slip_fraction: f64,
}

/// `grasp_msgs/msg/StepReport` (`ros2/grasp_msgs/msg/StepReport.msg`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepReport {
    /// Stamp, frame `world`.
    pub header: Header,
    /// Step index.
    pub step: u32,
    /// Status.
    pub status: String,
    /// Why, when not solved.
    pub reason: String,
    /// `native` or `clarabel`.
    pub solver: String,
    /// Warm-started.
    pub warm_start: bool,
    /// Newton (and interior-point) iterations.
    pub iterations: u32,
    /// Factorisations.
    pub factorizations: u32,
    /// Conjugate-gradient iterations.
    pub inner_iterations: u32,
    /// The smallest counted slip margin; NaN when none counts.
    pub smallest_slip_margin: f64,
    /// Its finger; empty when none counts.
    pub slip_margin_finger: String,
    /// NaN when absent.
    pub equilibrium_residual: f64,
    /// N; NaN when absent, infinite when unbounded.
    pub smallest_margin_n: f64,
    /// N; NaN when absent.
    pub margin_held_to_n: f64,
    /// Empty: none.
    pub margin_failing_finger: String,
    /// Every finger.
    pub fingers: Vec<FingerState>,
    /// Each hand of the grasp.
    pub hands: Vec<HandState>,
    /// Each servo of the grasp.
    pub servos: Vec<ServoState>,
}

/// `grasp_msgs/msg/HandState` (`ros2/grasp_msgs/msg/HandState.msg`), world frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HandState {
    /// Name.
    pub name: String,
    /// N.
    pub force_n: [f64; 3],
    /// N m.
    pub moment_nm: [f64; 3],
    /// m.
    pub translation_m: [f64; 3],
    /// rad.
    pub rotation_rad: [f64; 3],
}

/// `grasp_msgs/msg/ServoState` (`ros2/grasp_msgs/msg/ServoState.msg`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ServoState {
    /// Name.
    pub name: String,
    /// N.
    pub force_n: f64,
    /// m.
    pub travel_m: f64,
}

/// The 4-byte encapsulation header of a serialized ROS 2 message: plain CDR, little-endian.
pub const CDR_LE_HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// `message` as a serialized ROS 2 message: [`CDR_LE_HEADER`], then its little-endian CDR.
pub fn cdr_message<T: Serialize>(message: &T) -> Result<Vec<u8>, cdr_encoding::Error> {
    let body = cdr_encoding::to_vec::<T, byteorder::LittleEndian>(message)?;
    let mut out = Vec::with_capacity(4 + body.len());
    out.extend_from_slice(&CDR_LE_HEADER);
    out.extend_from_slice(&body);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A header at 1.5 s in frame "ab": int32 sec, uint32 nanosec, then the string (length
    /// with its terminator, bytes, NUL), each aligned to its size from the body's start.
    #[test]
    fn a_stamp_past_2038_is_none_not_a_clamped_one() {
        let last = i32::MAX as u64 * 1_000_000_000 + 999_999_999;
        assert_eq!(Time::from_ns(last).map(|t| t.sec), Some(i32::MAX));
        assert!(Time::from_ns(last + 1).is_none());
    }

    #[test]
    fn a_header_encodes_as_ros_2_cdr() {
        let h = Header {
            stamp: Time::from_ns(1_500_000_000).unwrap(),
            frame_id: "ab".into(),
        };
        let bytes = cdr_message(&h).unwrap();
        let mut want = CDR_LE_HEADER.to_vec();
        want.extend_from_slice(&1_i32.to_le_bytes());
        want.extend_from_slice(&500_000_000_u32.to_le_bytes());
        want.extend_from_slice(&3_u32.to_le_bytes());
        want.extend_from_slice(b"ab\0");
        assert_eq!(bytes, want);
    }

    /// A float64 after the string is aligned to 8 bytes from the body's start (not the file's).
    #[test]
    fn a_wrench_aligns_its_doubles_to_eight_bytes_of_the_body() {
        let w = WrenchStamped {
            header: Header {
                stamp: Time::ZERO,
                frame_id: "a".into(),
            },
            force: Vector3 {
                x: 1.0,
                y: 2.0,
                z: 3.0,
            },
            torque: Vector3 {
                x: 4.0,
                y: 5.0,
                z: 6.0,
            },
        };
        let bytes = cdr_message(&w).unwrap();
        // Body: 8 (stamp) + 4 (length) + 2 ("a\0") = 14, padded to 16, then six doubles.
        assert_eq!(bytes.len(), 4 + 16 + 48);
        assert_eq!(&bytes[4 + 16..4 + 24], &1.0_f64.to_le_bytes());
    }
}
