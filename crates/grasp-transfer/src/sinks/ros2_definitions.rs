//! The ROS 2 message definitions the MCAP's ROS 2 profile embeds as its schemas (`ros2msg`):
//! the standard interfaces it writes (their fields as the ROS 2 interface packages publish
//! them since Humble: `builtin_interfaces`, `std_msgs`, `geometry_msgs`, `tf2_msgs`,
//! `sensor_msgs`, `visualization_msgs`) and the project's own `grasp_msgs`, read from the
//! `.msg` files of the ROS 2 package shipped beside this crate (`ros2/grasp_msgs`, which a ROS
//! workspace builds with colcon).
//!
//! A schema is the type's definition followed by each type it uses (recursively, each once,
//! in order of first use), every one after a line of 80 `=` and a line `MSG: pkg/Name`: the
//! form `ros2 bag record` writes and every ROS 2 MCAP decoder reads.

/// One message type: its name (`pkg/msg/Name`) and its definition (fields and constants;
/// comments only in the project's own).
struct Definition {
    name: &'static str,
    text: &'static str,
}

/// The definitions, by name.
const DEFINITIONS: &[Definition] = &[
    Definition {
        name: "builtin_interfaces/msg/Time",
        text: "int32 sec\nuint32 nanosec\n",
    },
    Definition {
        name: "builtin_interfaces/msg/Duration",
        text: "int32 sec\nuint32 nanosec\n",
    },
    Definition {
        name: "std_msgs/msg/Header",
        text: "builtin_interfaces/Time stamp\nstring frame_id\n",
    },
    Definition {
        name: "std_msgs/msg/ColorRGBA",
        text: "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n",
    },
    Definition {
        name: "geometry_msgs/msg/Vector3",
        text: "float64 x\nfloat64 y\nfloat64 z\n",
    },
    Definition {
        name: "geometry_msgs/msg/Point",
        text: "float64 x\nfloat64 y\nfloat64 z\n",
    },
    Definition {
        name: "geometry_msgs/msg/Quaternion",
        text: "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n",
    },
    Definition {
        name: "geometry_msgs/msg/Pose",
        text: "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
    },
    Definition {
        name: "geometry_msgs/msg/Wrench",
        text: "geometry_msgs/Vector3 force\ngeometry_msgs/Vector3 torque\n",
    },
    Definition {
        name: "geometry_msgs/msg/WrenchStamped",
        text: "std_msgs/Header header\ngeometry_msgs/Wrench wrench\n",
    },
    Definition {
        name: "geometry_msgs/msg/Transform",
        text: "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n",
    },
    Definition {
        name: "geometry_msgs/msg/TransformStamped",
        text: "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n",
    },
    Definition {
        name: "tf2_msgs/msg/TFMessage",
        text: "geometry_msgs/TransformStamped[] transforms\n",
    },
    Definition {
        name: "sensor_msgs/msg/Image",
        text: "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\n\
               uint8 is_bigendian\nuint32 step\nuint8[] data\n",
    },
    Definition {
        name: "sensor_msgs/msg/CompressedImage",
        text: "std_msgs/Header header\nstring format\nuint8[] data\n",
    },
    Definition {
        name: "visualization_msgs/msg/UVCoordinate",
        text: "float32 u\nfloat32 v\n",
    },
    Definition {
        name: "visualization_msgs/msg/MeshFile",
        text: "string filename\nuint8[] data\n",
    },
    Definition {
        name: "visualization_msgs/msg/Marker",
        text: MARKER,
    },
    Definition {
        name: "visualization_msgs/msg/MarkerArray",
        text: "visualization_msgs/Marker[] markers\n",
    },
    Definition {
        name: "grasp_msgs/msg/FingerState",
        text: include_str!("../../ros2/grasp_msgs/msg/FingerState.msg"),
    },
    Definition {
        name: "grasp_msgs/msg/HandState",
        text: include_str!("../../ros2/grasp_msgs/msg/HandState.msg"),
    },
    Definition {
        name: "grasp_msgs/msg/ServoState",
        text: include_str!("../../ros2/grasp_msgs/msg/ServoState.msg"),
    },
    Definition {
        name: "grasp_msgs/msg/StepReport",
        text: include_str!("../../ros2/grasp_msgs/msg/StepReport.msg"),
    },
];

/// `visualization_msgs/msg/Marker` (its fields since Humble: textures, UV coordinates and
/// embedded mesh files included).
const MARKER: &str = "int32 ARROW=0\nint32 CUBE=1\nint32 SPHERE=2\nint32 CYLINDER=3\n\
int32 LINE_STRIP=4\nint32 LINE_LIST=5\nint32 CUBE_LIST=6\nint32 SPHERE_LIST=7\nint32 POINTS=8\n\
int32 TEXT_VIEW_FACING=9\nint32 MESH_RESOURCE=10\nint32 TRIANGLE_LIST=11\nint32 ADD=0\n\
int32 MODIFY=0\nint32 DELETE=2\nint32 DELETEALL=3\nstd_msgs/Header header\nstring ns\nint32 id\n\
int32 type\nint32 action\ngeometry_msgs/Pose pose\ngeometry_msgs/Vector3 scale\n\
std_msgs/ColorRGBA color\nbuiltin_interfaces/Duration lifetime\nbool frame_locked\n\
geometry_msgs/Point[] points\nstd_msgs/ColorRGBA[] colors\nstring texture_resource\n\
sensor_msgs/CompressedImage texture\nvisualization_msgs/UVCoordinate[] uv_coordinates\n\
string text\nstring mesh_resource\nvisualization_msgs/MeshFile mesh_file\n\
bool mesh_use_embedded_materials\n";

/// The definition of `name` (`pkg/msg/Name`), if it is one of [`DEFINITIONS`].
fn definition(name: &str) -> Option<&'static str> {
    DEFINITIONS.iter().find(|d| d.name == name).map(|d| d.text)
}

/// The message types a definition's fields use (`pkg/Name`, written `pkg/msg/Name`), in order.
fn used_types(text: &str) -> Vec<String> {
    text.lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter_map(|l| l.split_whitespace().next())
        .filter(|t| t.contains('/'))
        .map(|t| {
            let t = t.split('[').next().unwrap_or(t);
            let (pkg, name) = t.split_once('/').unwrap_or((t, ""));
            format!("{pkg}/msg/{name}")
        })
        .collect()
}

/// The `ros2msg` schema of `name` (`pkg/msg/Name`): its definition, then each type it uses
/// (recursively, each once); `None` for a type without a definition here.
pub fn schema_text(name: &str) -> Option<String> {
    let mut out = definition(name)?.to_string();
    let mut done = vec![name.to_string()];
    let mut queue = used_types(definition(name)?);
    while !queue.is_empty() {
        let t = queue.remove(0);
        if done.contains(&t) {
            continue;
        }
        let text = definition(&t)?;
        let short = t.replacen("/msg/", "/", 1);
        out.push_str(&format!("{}\nMSG: {short}\n{text}", "=".repeat(80)));
        queue.extend(used_types(text));
        done.push(t);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_type_a_definition_uses_is_defined() {
        for d in DEFINITIONS {
            for t in used_types(d.text) {
                assert!(definition(&t).is_some(), "{} uses {t}", d.name);
            }
            assert!(schema_text(d.name).is_some(), "{}", d.name);
        }
    }

    #[test]
    fn a_schema_lists_each_dependency_once_after_the_type_itself() {
        let s = schema_text("geometry_msgs/msg/WrenchStamped").unwrap();
        assert!(s.starts_with("std_msgs/Header header\ngeometry_msgs/Wrench wrench\n"));
        for dep in [
            "MSG: std_msgs/Header\n",
            "MSG: builtin_interfaces/Time\n",
            "MSG: geometry_msgs/Wrench\n",
            "MSG: geometry_msgs/Vector3\n",
        ] {
            assert_eq!(s.matches(dep).count(), 1, "{dep}");
        }
        assert_eq!(s.matches("MSG: ").count(), 4);
    }
}
