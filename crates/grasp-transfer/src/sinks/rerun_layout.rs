//! The default layout (a Rerun *blueprint*) a recording opens on: the 3-D view of the object,
//! fingers, force arrows and patch maps with, below it, every finger's patch seen flat
//! (pressure with its colour bar, and stick / slip / separated, with their key); the force
//! histories stacked on the right.
//!
//! ```text
//! +----------------------------+----------------------+
//! |                            | normal force [N]     |
//! |  hand-off (world/**)       +----------------------+
//! |                            | friction force [N]   |
//! +----------------------------+----------------------+
//! | f1 pressure | f1 state | ..| smallest margin [N]  |  (only when margins are logged)
//! | key         | ...          |                      |
//! +----------------------------+----------------------+
//! ```
//!
//! (the patches' grid only for fingers with flat views, [`super::patch_views`]). A recording of
//! no steps (`grasp margin --rrd`, the wrench surface) has nothing to plot: its layout is the
//! 3-D view alone. Built as
//! blueprint chunks by hand (the same archetypes the SDK's `rerun::blueprint` API logs),
//! because that API draws random view and container ids and stamps wall-clock times: here
//! every id is fixed, so the layout's bytes are the same from run to run (up to Rerun's
//! footer, see `rerun_log`). The user can still rearrange the views; the viewer keeps this
//! layout as the application's default.

use rerun::blueprint::components::{
    AutoLayout, AutoViews, ColumnShare, ContainerKind, IncludedContent, QueryExpression,
    RootContainer, RowShare, ViewClass,
};
use rerun::external::re_log_types::BlueprintActivationCommand;
use rerun::external::re_sdk_types::blueprint::archetypes::{
    ContainerBlueprint, TimePanelBlueprint, ViewBlueprint, ViewContents, ViewportBlueprint,
};
use rerun::external::re_sdk_types::datatypes::{Bool, Float32, Uuid};
use rerun::external::re_tuid::Tuid;
use rerun::log::{Chunk, ChunkId, LogMsg, RowId};
use rerun::{AsComponents, TimeCell, TimePoint};

/// Application id the recording and its layout share (the viewer pairs them by it).
pub const APPLICATION_ID: &str = "grasp";

/// The timeline the layout opens on: the schedule's time (the recording also has `step`).
pub const TIMELINE: &str = "schedule_time";

/// Store id of the layout (fixed, like the recording's).
const LAYOUT_ID: &str = "grasp-transfer-layout";

/// Origin of the layout's chunk and row ids (2023-01-01T00:00:00Z in ns: apart from the
/// recording's, which count up from 2024).
const ID_ORIGIN_NS: u64 = 1_672_531_200_000_000_000;

/// Share of the window's width given to the 3-D view (the plots take the rest).
const WORLD_COLUMN_SHARE: f32 = 3.0;
const PLOTS_COLUMN_SHARE: f32 = 2.0;

/// Share of the left column's height given to the 3-D view (the patches' grid takes the rest).
const WORLD_ROW_SHARE: f32 = 3.0;
const PATCHES_ROW_SHARE: f32 = 2.0;

/// One view of the layout: its class, title and the entity subtree it shows.
struct ViewSpec {
    id: u128,
    class: &'static str,
    name: String,
    origin: String,
}

fn view(id: u128, class: &'static str, name: &str, origin: &str) -> ViewSpec {
    ViewSpec {
        id,
        class,
        name: name.into(),
        origin: origin.into(),
    }
}

/// What a recording holds, so that its layout has a view for each part and none left empty.
#[derive(Clone, Copy, Debug)]
pub struct LayoutContent<'a> {
    /// Steps are logged (a hand-off): the force plots. Without steps (a grasp's wrench
    /// surface) the layout is the 3-D view alone.
    pub steps: bool,
    /// The smallest margin is logged at each step: its plot.
    pub margins: bool,
    /// A finger stands on a mount: the plot of the cores' displacements.
    pub mounts: bool,
    /// The fingers whose patches have flat views.
    pub flat: &'a [String],
    /// The fingers whose sensors have gel images: their image and height views.
    pub gels: &'a [String],
}

/// The 3-D view and the plots, in the order they are stacked (the 3-D view alone without
/// steps).
fn views(steps: bool, margins: bool, mounts: bool) -> Vec<ViewSpec> {
    if !steps {
        return vec![view(0x10, "3D", "grasp", "/world")];
    }
    let mut v = vec![
        view(0x10, "3D", "hand-off", "/world"),
        view(
            0x11,
            "TimeSeries",
            "normal force [N]",
            "/plots/normal_force",
        ),
        view(0x12, "TimeSeries", "friction force [N]", "/plots/friction"),
    ];
    if margins {
        v.push(view(
            0x13,
            "TimeSeries",
            "smallest margin [N]",
            "/plots/margin",
        ));
    }
    if mounts {
        v.push(view(0x14, "TimeSeries", "core moved [mm]", "/plots/core"));
    }
    v
}

/// Per finger with flat views, its pressure and state views, then the key.
fn patch_views(flat: &[String]) -> Vec<ViewSpec> {
    let mut v = Vec::new();
    for (i, name) in flat.iter().enumerate() {
        let id = 0x100 + 2 * i as u128;
        let origin = |part: &str| format!("/patches/{name}/{part}");
        v.push(view(
            id,
            "Tensor",
            &format!("{name} pressure [kPa]"),
            &origin("pressure"),
        ));
        v.push(view(
            id + 1,
            "2D",
            &format!("{name} stick / slip"),
            &origin("state"),
        ));
    }
    if !flat.is_empty() {
        v.push(view(0xff, "TextDocument", "key", "/patches/key"));
    }
    v
}

/// Per finger with a gel image, its shaded image and its height map (2-D views).
fn gel_views(gels: &[String]) -> Vec<ViewSpec> {
    let mut v = Vec::new();
    for (i, name) in gels.iter().enumerate() {
        let id = 0x200 + 2 * i as u128;
        let origin = |part: &str| format!("/tactile/{name}/{part}");
        v.push(view(id, "2D", &format!("{name} gel image"), &origin("gel")));
        v.push(view(
            id + 1,
            "2D",
            &format!("{name} gel height [m]"),
            &origin("gel_height"),
        ));
    }
    v
}

const ROOT_ID: u128 = 0x1;
const PLOTS_ID: u128 = 0x2;
const LEFT_ID: u128 = 0x3;
const PATCHES_ID: u128 = 0x4;

fn uuid(id: u128) -> Uuid {
    Uuid {
        bytes: id.to_be_bytes(),
    }
}

fn uuid_text(id: u128) -> String {
    let h = format!("{id:032x}");
    format!(
        "{}-{}-{}-{}-{}",
        &h[0..8],
        &h[8..12],
        &h[12..16],
        &h[16..20],
        &h[20..32]
    )
}

fn view_path(id: u128) -> String {
    format!("view/{}", uuid_text(id))
}

fn container_path(id: u128) -> String {
    format!("container/{}", uuid_text(id))
}

/// A view's two rows: its contents (`$origin/**`) and its blueprint.
fn view_rows(v: &ViewSpec) -> [(String, Box<dyn AsComponents>); 2] {
    let contents = ViewContents::new([QueryExpression("$origin/**".into())]);
    let blueprint = ViewBlueprint::new(ViewClass(v.class.into()))
        .with_display_name(v.name.as_str())
        .with_space_origin(v.origin.as_str());
    [
        (
            format!("{}/ViewContents", view_path(v.id)),
            Box::new(contents),
        ),
        (view_path(v.id), Box::new(blueprint)),
    ]
}

fn included(paths: impl IntoIterator<Item = String>) -> Vec<IncludedContent> {
    paths
        .into_iter()
        .map(|p| IncludedContent(p.as_str().into()))
        .collect()
}

/// The layout's rows: (entity path, archetype), children before their containers.
fn layout_rows(content: LayoutContent) -> Vec<(String, Box<dyn AsComponents>)> {
    let views = views(content.steps, content.margins, content.mounts);
    let mut patches = patch_views(content.flat);
    patches.extend(gel_views(content.gels));
    let mut rows: Vec<(String, Box<dyn AsComponents>)> = Vec::new();
    for v in views.iter().chain(&patches) {
        rows.extend(view_rows(v));
    }
    let has_plots = views.len() > 1;
    if has_plots {
        let plots = ContainerBlueprint::new(ContainerKind::Vertical)
            .with_display_name("forces")
            .with_contents(included(views[1..].iter().map(|v| view_path(v.id))));
        rows.push((container_path(PLOTS_ID), Box::new(plots)));
    }
    let mut left = view_path(views[0].id);
    if !patches.is_empty() {
        let grid = ContainerBlueprint::new(ContainerKind::Grid)
            .with_display_name("patches")
            .with_contents(included(patches.iter().map(|v| view_path(v.id))));
        rows.push((container_path(PATCHES_ID), Box::new(grid)));
        let column = ContainerBlueprint::new(ContainerKind::Vertical)
            .with_display_name("hand-off and patches")
            .with_contents(included([left, container_path(PATCHES_ID)]))
            .with_row_shares([
                RowShare(Float32(WORLD_ROW_SHARE)),
                RowShare(Float32(PATCHES_ROW_SHARE)),
            ]);
        rows.push((container_path(LEFT_ID), Box::new(column)));
        left = container_path(LEFT_ID);
    }
    let root = match has_plots {
        true => ContainerBlueprint::new(ContainerKind::Horizontal)
            .with_contents(included([left, container_path(PLOTS_ID)]))
            .with_col_shares([
                ColumnShare(Float32(WORLD_COLUMN_SHARE)),
                ColumnShare(Float32(PLOTS_COLUMN_SHARE)),
            ]),
        false => ContainerBlueprint::new(ContainerKind::Horizontal).with_contents(included([left])),
    };
    rows.push((container_path(ROOT_ID), Box::new(root)));
    let viewport = ViewportBlueprint::new()
        .with_root_container(RootContainer(uuid(ROOT_ID)))
        .with_auto_layout(AutoLayout(Bool(false)))
        .with_auto_views(AutoViews(Bool(false)));
    rows.push(("viewport".to_owned(), Box::new(viewport)));
    // Plots against the schedule's time (s), not the step index.
    let time = TimePanelBlueprint::new().with_timeline(TIMELINE);
    rows.push(("time_panel".to_owned(), Box::new(time)));
    rows
}

/// The layout as the messages of its own blueprint store, and the command that makes it the
/// active and default layout of the application (pass both to
/// `RecordingStream::send_blueprint`): a view for each part of `content`.
pub fn layout_messages(
    content: LayoutContent,
) -> Result<(Vec<LogMsg>, BlueprintActivationCommand), String> {
    let (rec, storage) = rerun::RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_id(LAYOUT_ID)
        .blueprint()
        .memory()
        .map_err(|e| e.to_string())?;
    rec.set_log_time_enabled(false);
    // The viewer reads blueprint rows on the `blueprint` timeline.
    let time: TimePoint = [("blueprint", TimeCell::from_sequence(0))]
        .into_iter()
        .collect();
    for (i, (path, arch)) in layout_rows(content).into_iter().enumerate() {
        let n = 2 * i as u64 + 1;
        let chunk_id = ChunkId::from_tuid(Tuid::from_nanos_and_inc(ID_ORIGIN_NS, n));
        let row_id = RowId::from_tuid(Tuid::from_nanos_and_inc(ID_ORIGIN_NS, n + 1));
        let chunk = Chunk::builder_with_id(chunk_id, path.as_str())
            .with_serialized_batches(row_id, time.clone(), arch.as_serialized_batches())
            .build()
            .map_err(|e| e.to_string())?;
        rec.send_chunk(chunk);
    }
    rec.flush_blocking().map_err(|e| e.to_string())?;
    let msgs = with_fixed_store_info(storage.take());
    let blueprint_id = match msgs.first() {
        Some(msg) => msg.store_id().clone(),
        None => return Err("the layout produced no messages".to_owned()),
    };
    let activation = BlueprintActivationCommand {
        blueprint_id,
        make_active: true,
        make_default: true,
    };
    Ok((msgs, activation))
}

/// The messages with one store announcement, its row id fixed (the SDK draws a random one
/// and may announce the store twice).
fn with_fixed_store_info(msgs: Vec<LogMsg>) -> Vec<LogMsg> {
    let mut announced = false;
    let mut out = Vec::with_capacity(msgs.len());
    for msg in msgs {
        match msg {
            LogMsg::SetStoreInfo(_) if announced => {}
            LogMsg::SetStoreInfo(mut info) => {
                info.row_id = Tuid::from_nanos_and_inc(ID_ORIGIN_NS, 0);
                announced = true;
                out.push(LogMsg::SetStoreInfo(info));
            }
            other => out.push(other),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uuid_text_is_the_standard_form_of_the_bytes() {
        let id = 0x0123_4567_89ab_cdef_0011_2233_4455_6677_u128;
        assert_eq!(uuid_text(id), "01234567-89ab-cdef-0011-223344556677");
        assert_eq!(uuid(id).bytes[0], 0x01);
        assert_eq!(uuid(id).bytes[15], 0x77);
    }

    fn view_count(content: LayoutContent) -> usize {
        let rows = layout_rows(content);
        assert_eq!(rows.last().map(|r| r.0.as_str()), Some("time_panel"));
        let views = rows.iter().filter(|(p, _)| p.matches('/').count() == 1);
        views.filter(|(p, _)| p.starts_with("view/")).count()
    }

    #[test]
    fn every_view_is_placed_once_and_the_margin_plot_only_when_asked() {
        let two = ["f1".to_string(), "f2".to_string()];
        for (margins, flat) in [(false, &[][..]), (true, &[][..]), (false, &two[..])] {
            let steps = true;
            for (mounts, gels) in [(false, &[][..]), (true, &two[..1])] {
                let n_views = view_count(LayoutContent {
                    steps,
                    margins,
                    mounts,
                    flat,
                    gels,
                });
                // Per finger with flat views, two; and the key; per gel image, two.
                let patches = 2 * flat.len() + usize::from(!flat.is_empty()) + 2 * gels.len();
                let plots = usize::from(margins) + usize::from(mounts);
                assert_eq!(n_views, 3 + plots + patches);
            }
        }
    }

    #[test]
    fn a_recording_of_no_steps_has_the_3d_view_alone() {
        let content = LayoutContent {
            steps: false,
            margins: false,
            mounts: false,
            flat: &[],
            gels: &[],
        };
        assert_eq!(view_count(content), 1);
        let rows = layout_rows(content);
        assert!(!rows.iter().any(|(p, _)| *p == container_path(PLOTS_ID)));
    }

    #[test]
    fn the_layout_is_the_same_on_every_call() {
        // Schema metadata is a hash map (its printed order varies): compare ids and columns.
        let content = |msgs: &[LogMsg]| -> Vec<String> {
            msgs.iter()
                .map(|m| match m {
                    LogMsg::ArrowMsg(store, a) => {
                        format!("{store:?} {:?} {:?}", a.chunk_id, a.batch.columns())
                    }
                    other => format!("{other:?}"),
                })
                .collect()
        };
        let flat = ["f1".to_string()];
        let layout = LayoutContent {
            steps: true,
            margins: true,
            mounts: true,
            flat: &flat,
            gels: &flat[..1],
        };
        let a = layout_messages(layout).unwrap();
        let b = layout_messages(layout).unwrap();
        assert_eq!(content(&a.0), content(&b.0));
        assert_eq!(a.1.blueprint_id, b.1.blueprint_id);
        let announcements = a.0.iter().filter(|m| matches!(m, LogMsg::SetStoreInfo(_)));
        assert_eq!(announcements.count(), 1);
        assert!(matches!(a.0.first(), Some(LogMsg::SetStoreInfo(_))));
    }
}
