//! The C interface from many threads at once: one library handle and its channel handles,
//! shared by pointer, give every thread the statuses and values one thread gets alone, and
//! each thread keeps its own last error. Under Miri (`cargo +nightly miri test --test capi`,
//! docs/reliability.md) this also checks the boundary's pointer code for data races.
#![allow(unsafe_code)]

use std::ffi::{c_int, CStr, CString};
use std::ptr::null_mut;

use bssrdf::*;
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::Grid;

/// Handles shared between threads.
#[derive(Clone, Copy)]
struct Shared {
    library: *const bssrdf_library,
    channels: [*const bssrdf_channel; 3],
}

// SAFETY: the header allows any number of threads to use a handle at once (handles are
// immutable); the test releases them only after every thread has joined.
unsafe impl Send for Shared {}
// SAFETY: as above.
unsafe impl Sync for Shared {}

/// Statuses and value bits of every lookup of the channels at `rounds` points from `seed`.
fn lookups(shared: Shared, seed: u64, rounds: usize) -> Vec<u64> {
    let mut rng = SplitMix64::seed_from_u64(seed);
    let mut out = Vec::new();
    for &ch in &shared.channels {
        for _ in 0..rounds {
            let theta = 1.7 * rng.next_f64();
            let (r, phi) = (3.0 * rng.next_f64(), 7.0 * rng.next_f64() - 3.5);
            let u = [0; 4].map(|_| rng.next_f64());
            let mut value = 0.0;
            let mut sample = bssrdf_sample {
                r: 0.0,
                phi: 0.0,
                pdf: 0.0,
            };
            let mut path = bssrdf_path_sample {
                theta: 0.0,
                r: 0.0,
                phi: 0.0,
                phi_prime: 0.0,
                pdf_theta: 0.0,
                pdf: 0.0,
            };
            // SAFETY: live handles (released after every thread has joined), valid outputs.
            unsafe {
                let status = bssrdf_channel_eval(ch, theta, r, phi, &mut value);
                out.extend([status as u64, value.to_bits()]);
                let status = bssrdf_channel_pdf(ch, theta, r, phi, &mut value);
                out.extend([status as u64, value.to_bits()]);
                let status = bssrdf_channel_sample(ch, theta, u[0], u[1], &mut sample);
                out.extend([status as u64, sample.r.to_bits(), sample.pdf.to_bits()]);
                let status = bssrdf_channel_sample_path(ch, u.as_ptr(), &mut path);
                out.extend([status as u64, path.theta.to_bits(), path.pdf.to_bits()]);
            }
        }
    }
    out
}

/// Makes a thread-specific failure and checks that the thread's last error names it.
fn own_last_error(shared: Shared, t: u64) {
    let name = CString::new(format!("no-such-material-{t}")).unwrap();
    let mut channel = null_mut();
    // SAFETY: a live library handle, a valid string and output.
    let status = unsafe { bssrdf_library_channel(shared.library, name.as_ptr(), 0, &mut channel) };
    assert_eq!(status, BSSRDF_ERROR_NOT_FOUND);
    // SAFETY: never NULL, valid until this thread's next failure.
    let message = unsafe { CStr::from_ptr(bssrdf_last_error_message()) };
    assert!(
        message.to_str().unwrap().contains(&format!("-{t}\"")),
        "{message:?}"
    );
}

#[test]
fn threads_sharing_c_handles_compute_what_one_thread_does() {
    let dir = tempfile::tempdir().unwrap();
    let path = crate::fixture::scene(dir.path(), &Grid::ferrier(10, 5, 14));
    let c_path = CString::new(path.to_str().unwrap()).unwrap();
    let mut library = null_mut();
    // SAFETY: a valid string and output.
    let status = unsafe { bssrdf_library_open(c_path.as_ptr(), BSSRDF_OPEN_MAP, &mut library) };
    assert_eq!(status, BSSRDF_OK);
    let channels = [0, 1, 2].map(|rgb: c_int| {
        let mut channel = null_mut();
        // SAFETY: a live library, a valid string and output.
        let status =
            unsafe { bssrdf_library_channel(library, c"skin1".as_ptr(), rgb, &mut channel) };
        assert_eq!(status, BSSRDF_OK);
        channel
    });
    let shared = Shared {
        library,
        channels: channels.map(|c| c.cast_const()),
    };
    let (threads, rounds) = if cfg!(miri) { (3, 2) } else { (8, 500) };
    let serial: Vec<Vec<u64>> = (0..threads).map(|t| lookups(shared, t, rounds)).collect();
    let parallel: Vec<Vec<u64>> = (0..threads)
        .map(|t| {
            std::thread::spawn(move || {
                own_last_error(shared, t);
                lookups(shared, t, rounds)
            })
        })
        .collect::<Vec<_>>()
        .into_iter()
        .map(|w| w.join().unwrap())
        .collect();
    assert!(parallel == serial, "threads differ from one thread alone");
    // SAFETY: every thread has joined; each handle released once.
    unsafe {
        for ch in channels {
            bssrdf_channel_release(ch);
        }
        bssrdf_library_close(library);
    }
}
