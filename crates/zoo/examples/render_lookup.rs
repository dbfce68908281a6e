//! What a renderer does with a library file, and nothing more: map it, make the lookup handles
//! of each material's colour channels once, then evaluate and sample them per shading point.
//! Bakes nothing.
//!
//! ```sh
//! bssrdf bake skin1 white-grapefruit-juice -o scene.bssrdf
//! cargo run --release -p bssrdf-zoo --example render_lookup -- scene.bssrdf
//! ```

use std::f64::consts::PI;
use std::io::Write;
use std::process::ExitCode;

use bssrdf_zoo::embed::{ChannelLookup, Library};
use bssrdf_zoo::materials::Rgb;

fn main() -> ExitCode {
    let Some(path) = std::env::args_os().nth(1) else {
        eprintln!("usage: render_lookup LIBRARY_FILE");
        return ExitCode::from(2);
    };
    match run(path.as_ref()) {
        Ok(()) => ExitCode::SUCCESS,
        // A closed pipe (`... | head`) ends the listing quietly.
        Err(e)
            if e.downcast_ref::<std::io::Error>()
                .is_some_and(|e| e.kind() == std::io::ErrorKind::BrokenPipe) =>
        {
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("render_lookup: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(path: &std::path::Path) -> Result<(), Box<dyn std::error::Error>> {
    // Scene load: map and validate the file, make one handle per material and channel.
    let library = Library::open_mmap(path)?;
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "{}: {} table(s), {} material(s)",
        path.display(),
        library.table_count(),
        library.materials().len()
    )?;
    let mut media: Vec<(String, [ChannelLookup; 3])> = Vec::new();
    for m in library.materials() {
        let [r, g, b] = Rgb::ALL.map(|c| library.channel(&m.name, c));
        media.push((m.name.clone(), [r?, g?, b?]));
    }
    // The handles keep the map alive; the library itself is no longer needed.
    drop(library);

    // Render time: per shading point, S_p(r, φ; θ) and importance samples, from any thread.
    for (name, rgb) in &media {
        writeln!(out, "\n{name}")?;
        for (channel, lookup) in ["r", "g", "b"].iter().zip(rgb) {
            writeln!(
                out,
                "  channel {channel}: rho' = {:.4}, sigma_t' = {:.4} /mm, eta = {}",
                lookup.rho_prime(),
                lookup.sigma_t_prime(),
                lookup.table().eta()
            )?;
            for theta_deg in [0.0, 45.0, 80.0] {
                let theta = f64::to_radians(theta_deg);
                let values: Vec<String> = [0.1, 1.0, 5.0]
                    .iter()
                    .flat_map(|&r_mm| {
                        [0.0, PI].map(|phi| {
                            let s = lookup.eval(theta, r_mm, phi).unwrap_or(0.0);
                            format!("{s:.4e}")
                        })
                    })
                    .collect();
                let rho_eff = lookup.effective_albedo(theta).unwrap_or(0.0);
                writeln!(
                    out,
                    "    θ = {theta_deg:>2}°: S at r = 0.1/1/5 mm, φ = 0/π: {} /mm²; ρ_eff = {rho_eff:.4}",
                    values.join(" ")
                )?;
                if let Some(s) = lookup.sample(theta, 0.5, 0.3) {
                    let weight = lookup.eval(theta, s.r, s.phi).unwrap_or(0.0) / s.pdf;
                    writeln!(
                        out,
                        "      sample: r = {:.4} mm, φ = {:+.3} rad, pdf = {:.4e} /mm², S/pdf = {weight:.4}",
                        s.r, s.phi, s.pdf
                    )?;
                }
            }
        }
    }
    Ok(())
}
