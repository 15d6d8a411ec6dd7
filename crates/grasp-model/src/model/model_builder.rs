//! Building a [`GraspModel`] from a validated scene and what reading it found (a
//! [`LoadedScene`]; a plain scene is loaded first): the object and its loads, each finger's
//! frame, patch and gaps (exact from the shapes or the thesis's quadratic form, less a
//! texture's heights), its contact pair and friction law, and its patch compliance (dense or
//! FFT, with its viscoelastic bodies), built once the memory it takes is known to be there.

use std::sync::Arc;

use nalgebra::Vector3;

use crate::error::{OutOfMemory, SceneError};
use crate::geometry::contact_frame::ContactFrame;
use crate::model::contact_pair::ContactPair;
use crate::model::equilibrium::MotionPlane;
use crate::model::finger_mount::{FingerMount, MOUNT_SOFTNESS_WARNING};
use crate::model::friction::FrictionLaw;
use crate::model::grasp_model::{Control, ExternalLoad, FingerModel, GraspModel, ObjectModel};
use crate::model::material::Material;
use crate::model::patch::Patch;
use crate::model::patch_compliance::{
    takes_fft, uses_fft, ComplianceChoice, ComplianceForm, PatchCompliance,
};
use crate::model::shared_spring::SharedSpring;
use crate::model::surface_gap::{exact_gaps, TipProfile};
use crate::model::viscous_contact::{BodyLaws, ViscousContact};
use crate::scene::loaded_scene::LoadedScene;
use crate::scene::memory_budget::{
    check_patch_room, dense_block_bytes, dense_blocks_problem, ComplianceBuild,
};
use crate::scene::scene_format::{FingerSpec, RadiusSpec, Scene};
use crate::scene::scene_geometry::SceneGeometry;
use crate::scene::texture_spec::texture_heights_m;
use crate::scene::texture_spec::{GapSpec, HeightGrid};

/// A first touch away from the contact point is reported when the gaps shift by more than this
/// fraction of the patch's half diagonal (smaller shifts are the rays' round-off).
const FIRST_TOUCH_TOLERANCE: f64 = 1e-9;

/// Compliance entries (summed over fingers) from which the blocks are built in parallel:
/// about 2 ms of work, well above a thread hand-off.
const PARALLEL_BUILD_ENTRIES: usize = 200_000;

impl GraspModel {
    /// Builds the model of a plain scene, one that names no file (loaded with
    /// [`LoadedScene::of_plain`]: its shapes posed from their specs), validating it first
    /// (patch compliances dense up to [`crate::scene::limits::AUTO_FFT_ABOVE_UNKNOWNS`]
    /// unknowns, FFT above). A scene read with its files: [`GraspModel::from_loaded`].
    pub fn from_scene(scene: &Scene) -> Result<GraspModel, SceneError> {
        Self::from_scene_with(scene, ComplianceChoice::Auto)
    }

    /// [`GraspModel::from_scene`] with the patch compliances in the form `compliance` picks.
    pub fn from_scene_with(
        scene: &Scene,
        compliance: ComplianceChoice,
    ) -> Result<GraspModel, SceneError> {
        Self::from_loaded_with(&LoadedScene::of_plain(scene.clone())?, compliance)
    }

    /// Builds the model from a scene as read (its shapes, surface and height maps), validating
    /// it first (patch compliances dense up to
    /// [`crate::scene::limits::AUTO_FFT_ABOVE_UNKNOWNS`] unknowns, FFT above).
    pub fn from_loaded(scene: &LoadedScene) -> Result<GraspModel, SceneError> {
        Self::from_loaded_with(scene, ComplianceChoice::Auto)
    }

    /// [`GraspModel::from_loaded`] with the patch compliances in the form `compliance` picks.
    pub fn from_loaded_with(
        scene: &LoadedScene,
        compliance: ComplianceChoice,
    ) -> Result<GraspModel, SceneError> {
        scene.validate()?;
        Self::from_validated_with(scene, compliance)
    }

    /// Builds the model of a scene the caller has validated ([`LoadedScene::validate`]: a batch
    /// checks its memory in between), with the patch compliances in the form `compliance`
    /// picks.
    pub fn from_validated_with(
        loaded: &LoadedScene,
        compliance: ComplianceChoice,
    ) -> Result<GraspModel, SceneError> {
        let scene = &loaded.scene;
        if scene.fingers.is_empty() {
            return Err(SceneError::Invalid(vec![crate::error::InputProblem {
                path: "fingers".into(),
                message: "is empty".into(),
                fix: "list at least one finger".into(),
            }]));
        }
        check_dense_bytes(loaded, compliance)?;
        let mut object = object_model(scene, &loaded.geometry);
        // The fingers' compliance blocks are independent: build them in parallel when they
        // are large enough to pay for the threads (the same numbers either way).
        let entries: usize = scene
            .fingers
            .iter()
            .map(|f| (3 * f.patch.grid[0] * f.patch.grid[1]).pow(2))
            .sum();
        let built: Vec<(FingerModel, Vec<String>)> =
            if entries >= PARALLEL_BUILD_ENTRIES && scene.fingers.len() > 1 {
                use rayon::prelude::*;
                scene
                    .fingers
                    .par_iter()
                    .enumerate()
                    .map(|(i, f)| finger_model(i, f, &object, &loaded.geometry, compliance))
                    .collect::<Result<_, _>>()?
            } else {
                scene
                    .fingers
                    .iter()
                    .enumerate()
                    .map(|(i, f)| finger_model(i, f, &object, &loaded.geometry, compliance))
                    .collect::<Result<_, _>>()?
            };
        let mut fingers = Vec::with_capacity(built.len());
        for (f, warnings) in built {
            object.scene_warnings.extend(warnings);
            fingers.push(f);
        }
        for (i, f) in fingers.iter().enumerate() {
            let warnings =
                f.contact
                    .layer_warnings(&f.patch.grid, &format!("fingers[{i}]"), &f.name);
            object.scene_warnings.extend(warnings);
        }
        let model = Self::from_parts(fingers, object);
        // The program's assembly and the solve allocate ordinarily: check they will fit.
        model
            .solve_size()
            .check_room()
            .map_err(|source| SceneError::OutOfMemory {
                path: "fingers".into(),
                source,
            })?;
        Ok(model)
    }
}

fn v3(a: &[f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

/// The object, its loads and the plane of a scene, and what the model keeps of its geometry
/// (the shape's warnings, the posed object and tip shapes, the object's triangles).
fn object_model(scene: &Scene, geometry: &SceneGeometry) -> ObjectModel {
    let plane = scene.planar.as_ref().map(|p| {
        let p = v3(&p.normal).normalize();
        let hint = if p.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let e1 = (hint - p * p.dot(&hint)).normalize();
        let e2 = p.cross(&e1);
        MotionPlane { e1, e2, normal: p }
    });
    let o = &scene.object;
    let center_of_mass_m = v3(&o.center_of_mass);
    let mut loads = Vec::new();
    if o.weight > 0.0 {
        loads.push(ExternalLoad {
            force_n: v3(&o.gravity).normalize() * o.weight,
            point_m: center_of_mass_m,
        });
    }
    for r in &o.external_forces {
        loads.push(ExternalLoad {
            force_n: v3(&r.force),
            point_m: v3(&r.at),
        });
    }
    ObjectModel {
        center_of_mass_m,
        loads,
        material: Material::from(&o.material),
        layer_thickness_m: o.material.layer_thickness_m(),
        relaxation: o.material.relaxation().cloned(),
        plane,
        kind: scene.model,
        scene_warnings: geometry.warnings().to_vec(),
        shape: geometry.shape.clone(),
        surface: geometry.surface.clone(),
        tip_shapes: geometry.tips.clone(),
        gap: scene.gap,
        springs: shared_springs(scene, plane.as_ref()),
    }
}

/// The scene's hands and servos, their fingers by scene index (validation checked that each
/// names a finger).
fn shared_springs(scene: &Scene, plane: Option<&MotionPlane>) -> Vec<SharedSpring> {
    let index = |names: &[String]| -> Vec<usize> {
        names
            .iter()
            .filter_map(|n| scene.fingers.iter().position(|f| &f.name == n))
            .collect()
    };
    let hands = scene
        .hands
        .iter()
        .map(|h| SharedSpring::hand(h, index(&h.fingers), plane));
    let servos = scene
        .servos
        .iter()
        .map(|s| SharedSpring::servo(s, index(&s.fingers)));
    hands.chain(servos).collect()
}

/// Refuses a scene whose dense patch compliances under `compliance` would exceed
/// `MAX_COMPLIANCE_BYTES` (validation checks the automatic choice; a caller that forces the
/// dense matrix on a fine grid is refused here, before anything is allocated).
fn check_dense_bytes(scene: &LoadedScene, compliance: ComplianceChoice) -> Result<(), SceneError> {
    let dense = |f: &FingerSpec| !takes_fft(scene, f, compliance);
    match dense_blocks_problem(scene, &scene.geometry, dense) {
        None => Ok(()),
        Some(p) => Err(SceneError::Invalid(vec![p])),
    }
}

/// Finger `i` of a scene, prepared (offset 0 until the model places it), with the warning its
/// gaps give (a first touch away from the contact point).
fn finger_model(
    i: usize,
    f: &crate::scene::scene_format::FingerSpec,
    object: &ObjectModel,
    geometry: &SceneGeometry,
    compliance: ComplianceChoice,
) -> Result<(FingerModel, Vec<String>), SceneError> {
    let frame = ContactFrame::new(
        v3(&f.contact_point),
        v3(&f.normal),
        f.tangent.as_ref().map(v3),
        object.plane.map(|p| p.normal),
    );
    check_patch_room(i, &f.name, f.patch.grid)?;
    let (patch, gap_warning) = finger_patch(i, f, &frame, object, geometry.height_map(i))?;
    let exact_gaps = gap_kind(f, object) == GapSpec::Exact && object.shape.is_some();
    let material = Material::from(&f.material);
    let contact = ContactPair::new(
        &material,
        f.material.layer_thickness_m(),
        &object.material,
        object.layer_thickness_m,
    );
    let friction = FrictionLaw::from_spec(&f.friction, &material, &object.material);
    let n_tangential = f.tangential_unknowns(object.plane.is_some());
    let grid = patch.grid;
    let fft = uses_fft(compliance, grid.len().saturating_mul(1 + n_tangential));
    let form = ComplianceForm {
        grid,
        n_tangential,
        fft,
    };
    let laws = BodyLaws {
        finger: f.material.relaxation(),
        object: object.relaxation.as_ref(),
    };
    let (mut compliance_m_per_n, viscous) = finger_compliance(i, f, &contact, form, laws)?;
    let mount = f.mount.as_ref().map(|m| {
        let planar = object.plane.is_some();
        let centres = patch.centres_m.clone();
        Arc::new(FingerMount::new(m, centres, n_tangential, planar))
    });
    let mut warnings: Vec<String> = gap_warning.into_iter().collect();
    if let Some(m) = &mount {
        warnings.extend(mount_softness_warning(i, &f.name, m, &compliance_m_per_n));
        compliance_m_per_n = compliance_m_per_n.with_mount(m);
    }
    let control = match (f.control.normal_load_n(), f.control.approach_m()) {
        (Some(p), _) => Control::NormalLoad { newtons: p },
        (None, Some(d)) => Control::Approach { metres: d },
        (None, None) => Control::Held,
    };
    let finger = FingerModel {
        name: f.name.clone(),
        scene_index: i,
        frame,
        patch,
        material,
        contact,
        friction,
        n_tangential,
        compliance_m_per_n,
        control,
        mount,
        viscous,
        offset: 0,
        exact_gaps,
    };
    Ok((finger, warnings))
}

/// The warning of finger `i` (`name`) whose mount is more than [`MOUNT_SOFTNESS_WARNING`]
/// times as compliant as its contact's `compliance` (m/N): the contact's part of their sum
/// keeps only about `f64::EPSILON` times that ratio of its relative precision.
fn mount_softness_warning(
    i: usize,
    name: &str,
    mount: &FingerMount,
    compliance: &PatchCompliance,
) -> Option<String> {
    let softness = mount.largest_diagonal() / compliance.max_diagonal();
    (softness > MOUNT_SOFTNESS_WARNING).then(|| {
        format!(
            "fingers[{i}] `{name}`: the mount is {softness:.1e} times as compliant as the \
             contact, so the contact's compliance keeps only about {:.0e} of its digits \
             beside it; a finger this soft is a force source: prescribe `normal_load`",
            f64::EPSILON * softness
        )
    })
}

/// Finger `i`'s patch compliance (and its viscoelastic bodies'), built once the memory it
/// takes is known to be there ([`crate::allocation::check_room`]) and from fallibly allocated
/// tables and spectra: a refusal is [`SceneError::OutOfMemory`] at the finger's grid, naming
/// the grid and what the compliance holds in all (the kernel table and the FFT operator's
/// spectra, or the dense matrix).
fn finger_compliance(
    i: usize,
    f: &FingerSpec,
    contact: &ContactPair,
    form: ComplianceForm,
    laws: BodyLaws,
) -> Result<(PatchCompliance, Option<Arc<ViscousContact>>), SceneError> {
    let ComplianceForm {
        ref grid,
        n_tangential,
        fft,
    } = form;
    let (nx, ny) = (grid.nx, grid.ny);
    let (kept, kept_bytes) = match fft {
        true => (
            "influence spectra",
            crate::model::compliance_operator::ComplianceOperator::memory_estimate_bytes(
                grid,
                n_tangential,
                true,
            ) as u64,
        ),
        false => (
            "compliance matrix",
            dense_block_bytes((nx * ny * (1 + n_tangential)) as u64),
        ),
    };
    let build = ComplianceBuild {
        finger: i,
        name: &f.name,
        grid: [nx, ny],
        kept,
        kept_bytes,
    };
    build.check_room()?;
    let refused = |e: OutOfMemory| build.refused(e);
    let built = match laws.are_elastic() {
        true => PatchCompliance::build(grid, contact, n_tangential, fft).map(|c| (c, None)),
        false => contact.kernel_table(grid).map(Arc::new).and_then(|table| {
            let viscous = ViscousContact::new(contact, &table, form, laws)?;
            let c = PatchCompliance::from_table(&table, n_tangential, fft)?;
            Ok((c, viscous.map(Arc::new)))
        }),
    };
    built.map_err(refused)
}

/// How finger `f`'s smooth gap is computed: its own `gap`, else the scene's, else exact with
/// a shape and quadratic without.
fn gap_kind(f: &FingerSpec, object: &ObjectModel) -> GapSpec {
    f.gap.or(object.gap).unwrap_or(match object.shape {
        Some(_) => GapSpec::Exact,
        None => GapSpec::Quadratic,
    })
}

/// Finger `i`'s patch: its elements and initial gaps, smooth (exact from the shapes,
/// `model/surface_gap.rs`, or the thesis's quadratic form, Johnson 4.1) less its texture's
/// heights (`map`: its height map's, when the texture is one), and the warning of a first
/// touch away from the contact point.
fn finger_patch(
    i: usize,
    f: &FingerSpec,
    frame: &ContactFrame,
    object: &ObjectModel,
    map: Option<&HeightGrid>,
) -> Result<(Patch, Option<String>), SceneError> {
    let (patch, warning) = smooth_patch(i, f, frame, object)?;
    let Some(texture) = &f.texture else {
        return Ok((patch, warning));
    };
    let element = [patch.grid.hx, patch.grid.hy];
    let heights = texture_heights_m(texture, map, &patch.centres_m, element).map_err(|e| {
        SceneError::Invalid(vec![crate::error::InputProblem {
            path: format!("fingers[{i}].texture"),
            message: e,
            fix: "give a texture that covers the patch (see the scene schema)".into(),
        }])
    })?;
    Ok((patch.with_texture(&heights), warning))
}

/// Finger `i`'s patch with its smooth gaps (see [`finger_patch`]).
fn smooth_patch(
    i: usize,
    f: &FingerSpec,
    frame: &ContactFrame,
    object: &ObjectModel,
) -> Result<(Patch, Option<String>), SceneError> {
    let shape = match (gap_kind(f, object), &object.shape) {
        (GapSpec::Exact, Some(shape)) => shape,
        _ => {
            let tip = tip_curvatures_per_m(f, frame);
            let obj = object_curvatures_per_m(f);
            let curvature = [tip[0] + obj[0], tip[1] + obj[1]];
            return Ok((Patch::new(f.patch.size, f.patch.grid, curvature), None));
        }
    };
    let flat = Patch::new(f.patch.size, f.patch.grid, [0.0, 0.0]);
    let reach_m = 0.5 * f.patch.size[0].hypot(f.patch.size[1]);
    let solid = object.tip_shapes.get(i).and_then(Option::as_ref);
    let tip = TipProfile::of(f, frame, solid);
    let gaps = exact_gaps(&shape.0, frame, &tip, &flat.centres_m, reach_m).map_err(|e| {
        SceneError::Invalid(vec![crate::error::InputProblem {
            path: format!("fingers[{i}].contact_point"),
            message: e,
            fix: "move the contact onto the object's surface with its normal into the object, \
                  or set the finger's `gap` to \"quadratic\""
                .into(),
        }])
    })?;
    let warning = (gaps.first_touch_shift_m > FIRST_TOUCH_TOLERANCE * reach_m).then(|| {
        format!(
            "fingers[{i}] ({}): the fingertip first touches the object {:.3e} m closer than at \
             the contact point (the surfaces curve or tilt toward each other there): its gaps and \
             approach are measured from that first touch; move the contact to where the \
             surfaces first meet",
            f.name, gaps.first_touch_shift_m
        )
    });
    let patch = flat.with_gaps(gaps.gap_m, gaps.off_surface, gaps.off_object);
    Ok((patch, warning))
}

/// The fingertip's curvatures along `t1`, `t2`, 1/m: a sphere `1/R` both ways; a cylinder
/// `1/R` across its axis and 0 along it (the axis lies along `t1` or `t2`, checked by
/// validation); flat 0 (the gap of two curved bodies: Johnson 4.1, curvatures added along
/// common principal directions).
pub fn tip_curvatures_per_m(
    f: &crate::scene::scene_format::FingerSpec,
    frame: &ContactFrame,
) -> [f64; 2] {
    if let Some(r) = f.tip_radius {
        return [1.0 / r, 1.0 / r];
    }
    let Some(tip) = &f.tip else {
        return [0.0, 0.0];
    };
    if let Some(s) = &tip.sphere {
        return [1.0 / s.radius, 1.0 / s.radius];
    }
    match &tip.cylinder {
        Some(c) => {
            let a = v3(&c.axis).normalize();
            match a.dot(&frame.t1).abs() >= a.dot(&frame.t2).abs() {
                true => [0.0, 1.0 / c.radius],
                false => [1.0 / c.radius, 0.0],
            }
        }
        None => [0.0, 0.0],
    }
}

/// The object's curvatures along `t1`, `t2` at finger `f`'s contact, 1/m (0: flat).
pub fn object_curvatures_per_m(f: &crate::scene::scene_format::FingerSpec) -> [f64; 2] {
    match f.object_radius {
        None => [0.0, 0.0],
        Some(RadiusSpec::Isotropic(r)) => [1.0 / r, 1.0 / r],
        Some(RadiusSpec::Principal([a, b])) => {
            [a.map_or(0.0, |r| 1.0 / r), b.map_or(0.0, |r| 1.0 / r)]
        }
    }
}
