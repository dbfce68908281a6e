use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::Pbd;
use bssrdf_zoo::table::{bake_lobes, GridPreset, Lobes};
fn main() {
    let a: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().unwrap())
        .collect();
    let (eta, rho) = (a[0], a[1]);
    let lobes = Lobes::for_eta(eta);
    let grid = GridPreset::Default.grid(eta, lobes);
    let (table, _) = bake_lobes(eta, Moments::Exact, &grid, true, lobes).unwrap();
    let view = table.view();
    let nodes: Vec<f64> = view
        .axes()
        .theta()
        .as_slice()
        .iter()
        .map(|t| t.to_degrees())
        .collect();
    println!("theta nodes {:?}", &nodes[nodes.len().saturating_sub(6)..]);
    let pbd = Pbd::new(rho, Boundary::new(eta, Moments::Exact).unwrap()).unwrap();
    let end = if eta < 1.0 {
        eta.asin()
    } else {
        std::f64::consts::FRAC_PI_2
    };
    for k in 0..=20 {
        let below = 5f64.to_radians() * (1.0 - k as f64 / 20.0).powi(3);
        let theta = (end - below).min(end - 1e-7);
        let want = pbd.effective_albedo(theta);
        let got = view.effective_albedo(rho, theta).unwrap();
        let bare = view.with_ridge(false).effective_albedo(rho, theta).unwrap();
        println!(
            "{:9.4} pbd {want:.6e} table {got:.6e} ({:+.2}%) nodes-part {bare:.6e} ridge {:.6e}",
            theta.to_degrees(),
            100.0 * (got / want - 1.0),
            got - bare
        );
    }
}
