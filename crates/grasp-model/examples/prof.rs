use grasp_model::{GraspModel, GraspSolver, Scene, SolveOptions, SolverChoice};
use std::time::Instant;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let text = std::fs::read_to_string(&args[1]).unwrap();
    let n: usize = args[2].parse().unwrap();
    let scene = Scene::from_json_str(&text).unwrap();
    let model = GraspModel::from_scene(&scene).unwrap();
    let o = SolveOptions {
        solver: SolverChoice::Native,
        ..SolveOptions::default()
    };
    let t = Instant::now();
    let (mut it, mut tn, mut ta, mut ts) = (0, 0.0, 0.0, 0.0);
    for _ in 0..n {
        let t0 = Instant::now();
        let mut g = GraspSolver::new(&model, o);
        ta += t0.elapsed().as_secs_f64();
        let s = g.solve(&model, &model.scene_loads_n()).unwrap();
        it = s.solver.iterations;
        tn += s.solver.solver_time_s;
        ts += s.solve_time_s;
    }
    let k = 1e3 / n as f64;
    println!(
        "{:.3} ms per solve (assembly {:.3}, solve_time {:.3}, native {:.3}), {it} iterations",
        t.elapsed().as_secs_f64() * k,
        ta * k,
        ts * k,
        tn * k
    );
}
