//! The disc hand-off (thesis section 4.2.3), style 2: the receiving pair ramps up while the
//! releasing pair is held; then the held pair is ramped down. Checks symmetry and completion.

mod support;

use grasp_transfer::{Stepper, TransferOptions, TransferSummary};

#[test]
fn receiving_pair_ramps_up_and_the_disc_ends_in_its_grasp() {
    let (scene, schedule) = support::transfer_example("disc_transfer");
    let names = scene.finger_names();
    let recs: Vec<_> = Stepper::new(&scene, &schedule, TransferOptions::default())
        .map(|r| r.unwrap())
        .collect();
    for r in &recs {
        assert!(r.solution.status.has_forces(), "t = {}", r.time_s);
        assert!(r.solution.residuals.unwrap().equilibrium_relative < 1e-9);
        let tol = 1e-6 * r.solution.load_scale_n;
        assert!((r.normal_force_n("f3") - r.normal_force_n("f4")).abs() <= tol);
    }
    let s = TransferSummary::from_records(&recs, &names);
    assert_eq!(s.releasing, vec!["f3", "f4"]);
    assert_eq!(s.receiving, vec!["f1", "f2"]);
    let half = s.half_transfer_time_s.unwrap();
    let full = s.full_transfer_time_s.unwrap();
    assert!(half > 0.0 && half < full, "half {half}, full {full}");
    assert!(s.failed_steps.is_empty());
}
