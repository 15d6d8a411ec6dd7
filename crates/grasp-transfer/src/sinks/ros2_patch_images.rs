//! A finger's patch and sensor fields as `sensor_msgs/msg/Image` for the ROS 2 profile: the
//! contact pressure (`32FC1`, Pa) and contact state (`mono8`, the codes of
//! [`super::element_maps::state_code`]) of its elements, and, where its sensor has them, its
//! taxel forces and marker displacements (`32FC3`, `[normal, t1, t2]` per pixel, N and m) and
//! its gel image (`rgb8`) and height map (`32FC1`, m).
//!
//! Every image is in the finger's contact frame (`<finger>/contact`) and laid out as a camera
//! whose optical z is the normal: pixel (column `i`, row `j`) is element (or taxel, marker)
//! `(i, j)`, `i` along `t1`, `j` along `t2` (row 0 at the most negative `t2`); the gel
//! image's camera order is the same. Little-endian pixels. A released finger (or a failed
//! step) has no image that step.

use grasp_model::FingerSpec;

use super::element_maps::state_code;
use super::ros2_messages::{contact_frame_id, Bytes, Header, Image, Time};
use super::sink::RunInfo;
use crate::stepper::StepRecord;

/// The image topics' last parts a finger has: its patch's two, and its sensor's.
pub fn image_kinds(spec: &FingerSpec) -> Vec<&'static str> {
    let mut kinds = vec!["pressure", "contact_state"];
    if let Some(s) = &spec.sensor {
        if s.taxels.is_some() {
            kinds.push("taxels");
        }
        if s.markers.is_some() {
            kinds.push("markers");
        }
        if s.gel.is_some() {
            kinds.extend(["gel", "gel_height"]);
        }
    }
    kinds
}

/// Row-major values `v` (`k = i ny + j`) in camera order (row `j`, column `i`).
fn camera_order<T: Copy>(v: &[T], nx: usize, ny: usize) -> Vec<T> {
    (0..ny)
        .flat_map(|j| (0..nx).map(move |i| v[i * ny + j]))
        .collect()
}

/// An image of `width` x `height` pixels of `bytes_per_pixel` bytes.
fn image(stamp: Time, frame: &str, size: [usize; 2], encoding: &str, data: Vec<u8>) -> Image {
    let [width, height] = size;
    let step = data.len().checked_div(height).unwrap_or(0);
    Image {
        header: Header {
            stamp,
            frame_id: frame.into(),
        },
        height: height as u32,
        width: width as u32,
        encoding: encoding.into(),
        is_bigendian: 0,
        step: step as u32,
        data: Bytes(data),
    }
}

fn f32_bytes(values: impl Iterator<Item = f64>) -> Vec<u8> {
    values.flat_map(|v| (v as f32).to_le_bytes()).collect()
}

/// Three-component readings `v` (`k = i ny + j`) of a `count` grid as a `32FC3` image.
fn triples(stamp: Time, frame: &str, count: [usize; 2], v: &[[f64; 3]]) -> Image {
    let [nx, ny] = count;
    let ordered = camera_order(v, nx, ny);
    let data = f32_bytes(ordered.iter().flatten().copied());
    image(stamp, frame, count, "32FC3", data)
}

/// Finger `name`'s images at step `r` (none when it is not in the grasp), by kind.
pub fn finger_images(
    run: &RunInfo,
    r: &StepRecord,
    name: &str,
    stamp: Time,
) -> Vec<(&'static str, Image)> {
    let (Some(model), Some(f)) = (
        run.model.fingers().iter().find(|m| m.name() == name),
        r.solution.finger(name),
    ) else {
        return Vec::new();
    };
    let frame = contact_frame_id(name);
    let g = &model.patch().grid;
    let (nx, ny) = (g.nx, g.ny);
    let pressure: Vec<f64> = f.elements.iter().map(|e| e.pressure_pa).collect();
    let pressure = f32_bytes(camera_order(&pressure, nx, ny).into_iter());
    let states: Vec<u8> = f.elements.iter().map(|e| state_code(e.state)).collect();
    let mut out = vec![
        (
            "pressure",
            image(stamp, &frame, [nx, ny], "32FC1", pressure),
        ),
        (
            "contact_state",
            image(
                stamp,
                &frame,
                [nx, ny],
                "mono8",
                camera_order(&states, nx, ny),
            ),
        ),
    ];
    if let Some(s) = r.sensors.iter().find(|s| s.finger == name) {
        if let Some(t) = &s.taxels {
            out.push(("taxels", triples(stamp, &frame, t.count, &t.force_n)));
        }
        if let Some(m) = &s.markers {
            out.push((
                "markers",
                triples(stamp, &frame, m.count, &m.displacement_m),
            ));
        }
        if let Some(gel) = &s.gel {
            let [w, h] = gel.camera_size().map(|v| v as usize);
            out.push((
                "gel",
                image(stamp, &frame, [w, h], "rgb8", gel.camera_rgb8()),
            ));
            let heights = gel.camera_height_f32_le();
            out.push(("gel_height", image(stamp, &frame, [w, h], "32FC1", heights)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_order_puts_t1_along_rows_and_t2_down_the_columns() {
        // nx = 3 along t1, ny = 2 along t2: element k = i ny + j holds 10 i + j.
        let v: Vec<u32> = (0..3)
            .flat_map(|i| (0..2).map(move |j| 10 * i + j))
            .collect();
        assert_eq!(camera_order(&v, 3, 2), vec![0, 10, 20, 1, 11, 21]);
    }
}
