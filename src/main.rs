use clarabel::algebra::*;
use clarabel::solver::*;
fn main() {
    momentlmi::faer_lapack::ensure_linked();
    let p = CscMatrix::zeros((3, 3));
    let q = vec![1.0, 0.0, 1.0];
    let a = CscMatrix::new(
        3,
        3,
        vec![0, 1, 2, 3],
        vec![0, 1, 2],
        vec![-1.0, -1.0, -1.0],
    );
    let b = vec![0.0, 1.0, 0.0];
    let cones = [PSDTriangleConeT(2)];
    let settings = DefaultSettings::default();
    let mut s = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).unwrap();
    s.solve();
    println!("{:?}", s.solution.obj_val);
}
