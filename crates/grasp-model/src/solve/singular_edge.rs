//! Where a contact's pressure is singular: at a sharp edge that cuts the contact off, where a
//! peak pressure is a property of the grid, not of the contact.
//!
//! A contact cut off by the object's edge (the elements past a box's edge face no surface), a
//! tip's rim, or a flat pad's own rim (a flat pad's patch is the pad, so its rim is a real
//! edge, as a flat punch's is) does not close smoothly as a Hertz contact does: its elastic
//! pressure grows without bound toward the edge, as the inverse square root of the distance
//! from it (the rigid flat punch of Johnson, *Contact Mechanics*, chapters 2 and 3). An
//! element's mean pressure there grows as the grid is refined (as `n^0.5` with `n` elements a
//! side). The forces, the area and the pressure away from the edge converge.

use crate::model::patch::Patch;

/// Whether the largest of the element normal forces `forces_n` (N, the patch's order) of a
/// loaded contact on `patch` lies at a sharp edge of the contact: an element beside one that
/// faces no surface (past the object's edge or the tip's rim), or, on a flat patch (the pad
/// itself), an element of its boundary ring. The peak pressure is then grid-dependent (see the
/// module).
pub(crate) fn peak_at_sharp_edge(patch: &Patch, forces_n: &[f64]) -> bool {
    let Some((k, peak)) = forces_n
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return false;
    };
    peak > 0.0 && (borders_no_surface(patch, k) || (!patch.curved && patch.on_boundary(k)))
}

/// Whether element `k` of `patch` borders (shares a side with) an element facing no surface.
fn borders_no_surface(patch: &Patch, k: usize) -> bool {
    if patch.off_surface.is_empty() {
        return false;
    }
    let g = &patch.grid;
    let (i, j) = (k / g.ny, k % g.ny);
    let off = |i: usize, j: usize| patch.is_off_surface(i * g.ny + j);
    (i > 0 && off(i - 1, j))
        || (i + 1 < g.nx && off(i + 1, j))
        || (j > 0 && off(i, j - 1))
        || (j + 1 < g.ny && off(i, j + 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4 x 4 patch, flat or curved, its last column past an edge when `cut`.
    fn patch(curved: bool, cut: bool) -> Patch {
        let mut p = Patch::new([4e-3, 4e-3], [4, 4], [0.0, 0.0]);
        p.curved = curved;
        if cut {
            p.off_surface = (0..16).map(|k| k % 4 == 3).collect();
        }
        p
    }

    /// Forces with their peak at element `k`.
    fn peak_at(k: usize) -> Vec<f64> {
        (0..16).map(|i| if i == k { 2.0 } else { 1.0 }).collect()
    }

    #[test]
    fn a_peak_beside_the_elements_past_an_edge_is_at_a_sharp_edge() {
        // Element (1, 2) borders (1, 3), past the edge.
        assert!(peak_at_sharp_edge(&patch(true, true), &peak_at(6)));
        // Element (1, 1) is inside.
        assert!(!peak_at_sharp_edge(&patch(true, true), &peak_at(5)));
    }

    #[test]
    fn a_flat_pads_rim_is_a_sharp_edge_a_curved_patchs_is_not() {
        assert!(peak_at_sharp_edge(&patch(false, false), &peak_at(0)));
        assert!(!peak_at_sharp_edge(&patch(false, false), &peak_at(5)));
        assert!(!peak_at_sharp_edge(&patch(true, false), &peak_at(0)));
    }

    #[test]
    fn an_unloaded_contact_has_no_peak() {
        assert!(!peak_at_sharp_edge(&patch(false, false), &[0.0; 16]));
        assert!(!peak_at_sharp_edge(&patch(false, false), &[]));
    }
}
