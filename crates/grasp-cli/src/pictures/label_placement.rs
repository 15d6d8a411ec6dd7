//! Labels placed without overlap: each label goes as close to its anchor as it can without
//! covering a label placed before it or a given obstacle (the marks it labels), searched on
//! rings of growing radius around the anchor (pixels, y down).

/// An axis-aligned box in pixels: top-left corner and size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LabelBox {
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
}

impl LabelBox {
    /// Whether the two boxes share interior (touching edges do not count).
    pub fn overlaps(&self, o: &LabelBox) -> bool {
        self.x < o.x + o.w && o.x < self.x + self.w && self.y < o.y + o.h && o.y < self.y + self.h
    }

    fn inside(&self, area: &LabelBox) -> bool {
        self.x >= area.x
            && self.y >= area.y
            && self.x + self.w <= area.x + area.w
            && self.y + self.h <= area.y + area.h
    }
}

/// Angles tried on each ring, in turns: right, then round both ways alternately.
const DIRECTIONS: [f64; 8] = [0.0, 0.125, -0.125, 0.25, -0.25, 0.375, -0.375, 0.5];

/// Boxes of `sizes` (width, height), in order, each centred on its anchor where that is free,
/// else at the nearest free spot found on rings spaced `gap` pixels apart (and `gap` from every
/// placed box and every obstacle), inside `area` where possible. A box that finds no free spot
/// within the area's reach keeps its anchor.
pub fn place_labels(
    anchors: &[(f64, f64)],
    sizes: &[(f64, f64)],
    area: LabelBox,
    gap: f64,
    obstacles: &[LabelBox],
) -> Vec<LabelBox> {
    let mut placed: Vec<LabelBox> = Vec::with_capacity(anchors.len());
    let reach = area.w.max(area.h);
    for (&(ax, ay), &(w, h)) in anchors.iter().zip(sizes) {
        let at = |dx: f64, dy: f64| LabelBox {
            x: ax - w / 2.0 + dx,
            y: ay - h / 2.0 + dy,
            w,
            h,
        };
        // A placed box grown by `gap` on every side: what a new box must stay out of.
        let free = |b: &LabelBox| {
            placed.iter().chain(obstacles).all(|p| {
                let grown = LabelBox {
                    x: p.x - gap,
                    y: p.y - gap,
                    w: p.w + 2.0 * gap,
                    h: p.h + 2.0 * gap,
                };
                !b.overlaps(&grown)
            }) && b.inside(&area)
        };
        let rings = (reach / gap.max(1.0)).ceil() as usize;
        let found = (0..=rings)
            .flat_map(|k| {
                DIRECTIONS
                    .iter()
                    .map(move |t| (k as f64 * gap.max(1.0), *t))
            })
            .map(|(r, t)| {
                let a = t * std::f64::consts::TAU;
                at(r * a.cos(), -r * a.sin())
            })
            .find(|b| free(b));
        placed.push(found.unwrap_or_else(|| at(0.0, 0.0)));
    }
    placed
}

#[cfg(test)]
mod tests {
    use super::*;

    const AREA: LabelBox = LabelBox {
        x: 0.0,
        y: 0.0,
        w: 500.0,
        h: 400.0,
    };

    fn no_two_overlap(b: &[LabelBox]) {
        for i in 0..b.len() {
            for j in i + 1..b.len() {
                assert!(!b[i].overlaps(&b[j]), "boxes {i} and {j} overlap: {b:?}");
            }
        }
    }

    #[test]
    fn labels_on_one_anchor_spread_without_overlap() {
        let anchors = vec![(250.0, 200.0); 12];
        let sizes: Vec<(f64, f64)> = (0..12).map(|i| (30.0 + 4.0 * i as f64, 13.0)).collect();
        let b = place_labels(&anchors, &sizes, AREA, 2.0, &[]);
        no_two_overlap(&b);
        assert!(b.iter().all(|x| x.inside(&AREA)), "{b:?}");
    }

    #[test]
    fn labels_keep_off_the_obstacles() {
        let dots: Vec<LabelBox> = (0..5)
            .map(|i| LabelBox {
                x: 240.0 + 4.0 * i as f64,
                y: 196.0,
                w: 8.0,
                h: 8.0,
            })
            .collect();
        let b = place_labels(&[(250.0, 200.0); 5], &[(30.0, 13.0); 5], AREA, 2.0, &dots);
        no_two_overlap(&b);
        assert!(
            b.iter().all(|x| dots.iter().all(|d| !x.overlaps(d))),
            "{b:?}"
        );
    }

    #[test]
    fn a_free_label_stays_centred_on_its_anchor() {
        let b = place_labels(
            &[(100.0, 50.0), (400.0, 300.0)],
            &[(40.0, 12.0); 2],
            AREA,
            2.0,
            &[],
        );
        assert_eq!(
            b[0],
            LabelBox {
                x: 80.0,
                y: 44.0,
                w: 40.0,
                h: 12.0
            }
        );
        assert_eq!(
            b[1],
            LabelBox {
                x: 380.0,
                y: 294.0,
                w: 40.0,
                h: 12.0
            }
        );
    }

    #[test]
    fn labels_near_an_edge_stay_inside_the_area() {
        let anchors = vec![(2.0, 2.0), (4.0, 3.0), (498.0, 398.0)];
        let b = place_labels(&anchors, &[(50.0, 14.0); 3], AREA, 2.0, &[]);
        no_two_overlap(&b);
        assert!(b.iter().all(|x| x.inside(&AREA)), "{b:?}");
    }

    #[test]
    fn touching_boxes_do_not_overlap_but_shared_interior_does() {
        let a = LabelBox {
            x: 0.0,
            y: 0.0,
            w: 10.0,
            h: 10.0,
        };
        let touching = LabelBox { x: 10.0, ..a };
        let sharing = LabelBox { x: 9.5, ..a };
        assert!(!a.overlaps(&touching) && a.overlaps(&sharing));
    }
}
