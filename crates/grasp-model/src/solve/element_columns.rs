//! A finger's elements in its JSON form: one record per element (`"elements"`) up to
//! [`COLUMNS_ABOVE_ELEMENTS`] elements, one array per field (`"element_fields"`) above, the
//! rule the recordings follow for their maps. Both forms are read back; the columns are
//! serialised straight from the elements, one field at a time, with no copy.
//!
//! `"element_fields"` holds the fields of [`ElementSolution`] under the same names, each an
//! array in element order (`k = i ny + j`): numbers for scalar fields, `[a, b]` pairs for
//! two-component fields, triples for `position_m` (and `viscous_displacement_m`, present on a
//! viscoelastic contact), state names for `state`.

use serde::de::Error as _;
use serde::ser::{SerializeMap, SerializeSeq};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::solve::solution::{ElementSolution, ElementState};

/// Fingers with more elements than this (64 x 64, where `--compliance auto` takes the FFT
/// operator and the recordings switch to maps) write their elements as columns; up to it every
/// element is its own record, as before fine patches existed.
pub const COLUMNS_ABOVE_ELEMENTS: usize = 64 * 64;

/// Whether a finger of `elements` elements writes them as columns.
pub fn is_columnar(elements: usize) -> bool {
    elements > COLUMNS_ABOVE_ELEMENTS
}

/// Serialises a finger's elements as one map entry, `"elements"` or `"element_fields"` (the
/// finger's `elements` field is flattened into it).
pub(crate) fn serialize<S: Serializer>(v: &[ElementSolution], s: S) -> Result<S::Ok, S::Error> {
    let mut m = s.serialize_map(Some(1))?;
    match is_columnar(v.len()) {
        true => m.serialize_entry("element_fields", &Columns(v))?,
        false => m.serialize_entry("elements", v)?,
    }
    m.end()
}

/// Reads a finger's elements from either form.
pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Vec<ElementSolution>, D::Error> {
    #[derive(Deserialize)]
    struct Either {
        elements: Option<Vec<ElementSolution>>,
        element_fields: Option<OwnedColumns>,
    }
    match Either::deserialize(d)? {
        Either {
            elements: Some(e),
            element_fields: None,
        } => Ok(e),
        Either {
            elements: None,
            element_fields: Some(c),
        } => c.into_elements().map_err(D::Error::custom),
        _ => Err(D::Error::custom(
            "a finger holds exactly one of `elements` and `element_fields`",
        )),
    }
}

/// The columns of a finger's elements, borrowed.
struct Columns<'a>(&'a [ElementSolution]);

/// One field of every element, serialised as an array without a copy.
struct Column<'a, T, F: Fn(&ElementSolution) -> T>(&'a [ElementSolution], F);

impl<T: Serialize, F: Fn(&ElementSolution) -> T> Serialize for Column<'_, T, F> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.0.len()))?;
        for e in self.0 {
            seq.serialize_element(&(self.1)(e))?;
        }
        seq.end()
    }
}

impl Serialize for Columns<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let e = self.0;
        let viscous = e.iter().any(|e| e.viscous_displacement_m.is_some());
        let mut m = s.serialize_map(Some(if viscous { 12 } else { 11 }))?;
        m.serialize_entry("index", &Column(e, |e| e.index))?;
        m.serialize_entry("local_m", &Column(e, |e| e.local_m))?;
        m.serialize_entry("position_m", &Column(e, |e| e.position_m))?;
        m.serialize_entry("normal_force_n", &Column(e, |e| e.normal_force_n))?;
        m.serialize_entry("tangential_force_n", &Column(e, |e| e.tangential_force_n))?;
        m.serialize_entry("pressure_pa", &Column(e, |e| e.pressure_pa))?;
        m.serialize_entry("traction_pa", &Column(e, |e| e.traction_pa))?;
        m.serialize_entry("gap_m", &Column(e, |e| e.gap_m))?;
        m.serialize_entry("slip_m", &Column(e, |e| e.slip_m))?;
        m.serialize_entry("step_slip_m", &Column(e, |e| e.step_slip_m))?;
        m.serialize_entry("state", &Column(e, |e| e.state))?;
        if viscous {
            m.serialize_entry(
                "viscous_displacement_m",
                &Column(e, |e| e.viscous_displacement_m),
            )?;
        }
        m.end()
    }
}

/// The columns as read back.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct OwnedColumns {
    index: Vec<[usize; 2]>,
    local_m: Vec<[f64; 2]>,
    position_m: Vec<[f64; 3]>,
    normal_force_n: Vec<f64>,
    tangential_force_n: Vec<[f64; 2]>,
    pressure_pa: Vec<f64>,
    traction_pa: Vec<[f64; 2]>,
    gap_m: Vec<f64>,
    slip_m: Vec<[f64; 2]>,
    step_slip_m: Vec<[f64; 2]>,
    state: Vec<ElementState>,
    #[serde(default)]
    viscous_displacement_m: Option<Vec<Option<[f64; 3]>>>,
}

impl OwnedColumns {
    /// The elements, one per row; every column must have as many rows as `index`.
    fn into_elements(self) -> Result<Vec<ElementSolution>, String> {
        let n = self.index.len();
        let lengths = [
            self.local_m.len(),
            self.position_m.len(),
            self.normal_force_n.len(),
            self.tangential_force_n.len(),
            self.pressure_pa.len(),
            self.traction_pa.len(),
            self.gap_m.len(),
            self.slip_m.len(),
            self.step_slip_m.len(),
            self.state.len(),
            self.viscous_displacement_m.as_ref().map_or(n, Vec::len),
        ];
        if lengths.iter().any(|&l| l != n) {
            return Err(format!(
                "the columns of `element_fields` differ in length ({n} indices, {lengths:?})"
            ));
        }
        Ok((0..n)
            .map(|k| ElementSolution {
                index: self.index[k],
                local_m: self.local_m[k],
                position_m: self.position_m[k],
                normal_force_n: self.normal_force_n[k],
                tangential_force_n: self.tangential_force_n[k],
                pressure_pa: self.pressure_pa[k],
                traction_pa: self.traction_pa[k],
                gap_m: self.gap_m[k],
                slip_m: self.slip_m[k],
                step_slip_m: self.step_slip_m[k],
                state: self.state[k],
                viscous_displacement_m: self.viscous_displacement_m.as_ref().and_then(|v| v[k]),
            })
            .collect())
    }
}
