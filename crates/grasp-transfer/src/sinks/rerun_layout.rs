//! The default layout (a Rerun *blueprint*) a recording opens on: the 3-D view of the object,
//! fingers, force arrows and patch maps on the left; the force histories stacked on the right.
//!
//! ```text
//! +----------------------------+----------------------+
//! |                            | normal force [N]     |
//! |  hand-off (world/**)       +----------------------+
//! |                            | friction force [N]   |
//! |                            +----------------------+
//! |                            | smallest margin [N]  |  (only when margins are logged)
//! +----------------------------+----------------------+
//! ```
//!
//! Built as blueprint chunks by hand (the same archetypes the SDK's `rerun::blueprint` API
//! logs), because that API draws random view and container ids and stamps wall-clock times:
//! here every id is fixed, so the layout's bytes are the same from run to run (up to Rerun's
//! footer, see `rerun_log`). The user can still rearrange the views; the viewer keeps this
//! layout as the application's default.

use rerun::blueprint::components::{
    AutoLayout, AutoViews, ColumnShare, ContainerKind, IncludedContent, QueryExpression,
    RootContainer, ViewClass,
};
use rerun::external::re_log_types::BlueprintActivationCommand;
use rerun::external::re_sdk_types::blueprint::archetypes::{
    ContainerBlueprint, ViewBlueprint, ViewContents, ViewportBlueprint,
};
use rerun::external::re_sdk_types::datatypes::{Bool, Float32, Uuid};
use rerun::external::re_tuid::Tuid;
use rerun::log::{Chunk, ChunkId, LogMsg, RowId};
use rerun::{AsComponents, TimeCell, TimePoint};

/// Application id the recording and its layout share (the viewer pairs them by it).
pub const APPLICATION_ID: &str = "grasp";

/// Store id of the layout (fixed, like the recording's).
const LAYOUT_ID: &str = "grasp-transfer-layout";

/// Origin of the layout's chunk and row ids (2023-01-01T00:00:00Z in ns: apart from the
/// recording's, which count up from 2024).
const ID_ORIGIN_NS: u64 = 1_672_531_200_000_000_000;

/// Share of the window's width given to the 3-D view (the plots take the rest).
const WORLD_COLUMN_SHARE: f32 = 3.0;
const PLOTS_COLUMN_SHARE: f32 = 2.0;

/// One view of the layout: its class, title and the entity subtree it shows.
struct ViewSpec {
    id: u128,
    class: &'static str,
    name: &'static str,
    origin: &'static str,
}

/// The views, in the order they are stacked.
fn views(margins: bool) -> Vec<ViewSpec> {
    let view = |id, class, name, origin| ViewSpec {
        id,
        class,
        name,
        origin,
    };
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
    v
}

const ROOT_ID: u128 = 0x1;
const PLOTS_ID: u128 = 0x2;

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

/// The layout's rows: (entity path, archetype), children before their containers.
fn layout_rows(margins: bool) -> Vec<(String, Box<dyn AsComponents>)> {
    let views = views(margins);
    let mut rows: Vec<(String, Box<dyn AsComponents>)> = Vec::new();
    for v in &views {
        let contents = ViewContents::new([QueryExpression("$origin/**".into())]);
        rows.push((
            format!("{}/ViewContents", view_path(v.id)),
            Box::new(contents),
        ));
        let view = ViewBlueprint::new(ViewClass(v.class.into()))
            .with_display_name(v.name)
            .with_space_origin(v.origin);
        rows.push((view_path(v.id), Box::new(view)));
    }
    let plots = ContainerBlueprint::new(ContainerKind::Vertical)
        .with_display_name("forces")
        .with_contents(
            views[1..]
                .iter()
                .map(|v| IncludedContent(view_path(v.id).as_str().into())),
        );
    rows.push((container_path(PLOTS_ID), Box::new(plots)));
    let root = ContainerBlueprint::new(ContainerKind::Horizontal)
        .with_contents([
            IncludedContent(view_path(views[0].id).as_str().into()),
            IncludedContent(container_path(PLOTS_ID).as_str().into()),
        ])
        .with_col_shares([
            ColumnShare(Float32(WORLD_COLUMN_SHARE)),
            ColumnShare(Float32(PLOTS_COLUMN_SHARE)),
        ]);
    rows.push((container_path(ROOT_ID), Box::new(root)));
    let viewport = ViewportBlueprint::new()
        .with_root_container(RootContainer(uuid(ROOT_ID)))
        .with_auto_layout(AutoLayout(Bool(false)))
        .with_auto_views(AutoViews(Bool(false)));
    rows.push(("viewport".to_owned(), Box::new(viewport)));
    rows
}

/// The layout as the messages of its own blueprint store, and the command that makes it the
/// active and default layout of the application (pass both to
/// `RecordingStream::send_blueprint`). `margins` adds the smallest-margin plot.
pub fn layout_messages(margins: bool) -> Result<(Vec<LogMsg>, BlueprintActivationCommand), String> {
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
    for (i, (path, arch)) in layout_rows(margins).into_iter().enumerate() {
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

    #[test]
    fn every_view_is_placed_once_and_the_margin_plot_only_when_asked() {
        for margins in [false, true] {
            let rows = layout_rows(margins);
            let views = rows.iter().filter(|(p, _)| p.matches('/').count() == 1);
            let n_views = views.filter(|(p, _)| p.starts_with("view/")).count();
            assert_eq!(n_views, 3 + usize::from(margins));
            assert_eq!(rows.last().map(|r| r.0.as_str()), Some("viewport"));
        }
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
        let a = layout_messages(true).unwrap();
        let b = layout_messages(true).unwrap();
        assert_eq!(content(&a.0), content(&b.0));
        assert_eq!(a.1.blueprint_id, b.1.blueprint_id);
        let announcements = a.0.iter().filter(|m| matches!(m, LogMsg::SetStoreInfo(_)));
        assert_eq!(announcements.count(), 1);
        assert!(matches!(a.0.first(), Some(LogMsg::SetStoreInfo(_))));
    }
}
