//! The lookups at arbitrary inputs: each input picks a table of one library file (the default
//! grid at η = 1.33 with θ sampling, two scene subsets of its albedo rows, the same without θ
//! sampling, small bakes at η = 0.75, 2.5 and at η = 1 with pbrt's moments, a radius axis of
//! three nodes: `bssrdf_testkit::lookups::tables`) and a model of the zoo (every registered kind,
//! `bssrdf_testkit::models::zoo`), and nine numbers (ρ′, θ, r, φ, four random numbers, σ′t), each
//! a special value (NaN, ±∞, ±0, subnormals, huge), any bit pattern, a table node a few ulps
//! off, or a point of its domain. The rules are the property tests' (`bssrdf_testkit::lookups`):
//! no panic, no NaN or negative value or density, each draw `None` or a valid point whose
//! density `pdf` gives, through `TableRef`, the Rust handles of the mapped file, the C
//! interface on the same file (bit for bit the Rust handles' results), and the models.
//!
//! `cargo +nightly fuzz run lookups` (an empty corpus is fine: every input of 83 bytes is a
//! valid case, shorter ones are padded with zeros).
#![no_main]
#![allow(unsafe_code)]

use std::sync::OnceLock;

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::table::{bake, Grid, GridPreset};
use libfuzzer_sys::fuzz_target;

use bssrdf_testkit::lookups::{
    check_capi, check_channel, check_model, check_view, inputs, model_inputs, open_tables, Opened,
};
use bssrdf_testkit::models::{documented_infinity, zoo, Built, WALK_THETA};

struct Fixture {
    opened: Opened,
    models: Vec<Built>,
}

fn fixture() -> &'static Fixture {
    static FIXTURE: OnceLock<Fixture> = OnceLock::new();
    FIXTURE.get_or_init(|| {
        let default = Grid::preset(GridPreset::Default);
        Fixture {
            opened: open_tables(bake(1.33, Moments::Exact, &default, true).unwrap().0),
            models: zoo(),
        }
    })
}

fuzz_target!(|data: &[u8]| {
    let mut bytes = [0u8; 83];
    let n = data.len().min(bytes.len());
    bytes[..n].copy_from_slice(&data[..n]);
    let selectors: [u8; 9] = std::array::from_fn(|k| bytes[2 + k]);
    let bits: [u64; 9] =
        std::array::from_fn(|k| u64::from_le_bytes(std::array::from_fn(|b| bytes[11 + 8 * k + b])));
    let fixture = fixture();

    let library = &fixture.opened.rust;
    let t = usize::from(bytes[0]) % library.table_count();
    let table = library.table(t).unwrap();
    let x = inputs(&table.view(), selectors, bits);
    check_view(&table.view(), &x);
    let rust = check_channel(&table, &x);
    // SAFETY: the open C handle of the file `library` maps.
    unsafe { check_capi(fixture.opened.c, t, rust.as_ref(), &x) };

    let built = &fixture.models[usize::from(bytes[1]) % fixture.models.len()];
    let x = model_inputs(WALK_THETA, selectors, bits);
    let infinite_ok = documented_infinity(built.kind, built.eta, x.theta, x.r, x.phi);
    check_model(built.model.as_ref(), &x, infinite_ok);
});
