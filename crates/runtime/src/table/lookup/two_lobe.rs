//! Evaluation of a two-lobe table: the harmonics' shares of E blended over the slice's rows,
//! and the two lobes rebuilt from them at the point (format-spec.md §10).

use super::*;
use crate::table::{node_sharpness, SHARES_PER_NODE};

/// What [`TableRef::harmonic_shares`] blends at the four radius nodes of a lookup's window.
pub(super) struct Shares {
    /// Per node, the four harmonics' shares of E.
    shares: [[f64; 4]; 4],
    /// Per node of the window, the sharpest lobe of the rows blended there (each [`ramped`] in
    /// by its row's weight); the nodes' own weights along r ramp these in turn into the cap of
    /// the rebuild ([`TableRef::two_lobe_cell`]).
    sharpest: [f32; 4],
}

/// Below this weight |ω| a row's sharpest lobe enters the cap of the rebuild in proportion to
/// its weight ([`ramped`]). Small: a row of little weight can still carry a sharp lobe the
/// blend needs (with 1/16 the far-tail spread points of `bssrdf bake --eta 1.05`'s check went
/// from within 10 % to 13–31 % off, at ρ′ < 0.1 towards grazing).
const CAP_RAMP_WEIGHT: f32 = 1e-3;

/// What a row of weight `w` whose sharpest lobe is `sharpness` (a concentration in [0, 1))
/// asks of the cap of the rebuild, the largest over the rows blended: its sharpness from
/// |w| = [`CAP_RAMP_WEIGHT`] up, a proportional part of it below. With the sharpness of every
/// row of nonzero weight the cap jumped where a row's weight left 0: one ulp of θ off a node
/// moved a value of a walk table by up to 337 %. Ramped, the cap is continuous in the weights,
/// and at a node (one row of weight 1) still that node's own.
#[inline(always)]
fn ramped(w: f32, sharpness: f32) -> f32 {
    if w.abs() >= CAP_RAMP_WEIGHT {
        sharpness
    } else {
        ramp_below(w, sharpness)
    }
}

/// [`ramped`] below [`CAP_RAMP_WEIGHT`], out of line: the branch above is nearly always taken
/// one way, and as a branch it leaves the cap independent of the weights' values (computed
/// from them, the cap waited on them and a two-lobe evaluation took 17 % longer; this way
/// 7 %, a draw 4 %: `ETA=1.2 N=2000000 cargo run --release -p bssrdf-zoo --example lookup_loop --
/// eval` against the cap of every row, fastest of three in alternation).
#[cold]
#[inline(never)]
fn ramp_below(w: f32, sharpness: f32) -> f32 {
    w.abs() * (1.0 / CAP_RAMP_WEIGHT) * sharpness
}

impl TableRef<'_> {
    /// The shares of E that the harmonics μ₁ … μ₄ of a two-lobe table carry, rμₙ/E, at the four
    /// radius nodes `first..first + 4`: per node, the mean over the slice's rows that hold
    /// energy there of each row's own shares, weighted by the slice's weights ω (as the
    /// concentration c is, [`AlbedoWeights::c_scale`]). Row by row the harmonics are E_βc and
    /// E_βc² (the first array's one lobe carries the first two, `table::bake`), rμ₃ and rμ₄ (the
    /// second array). Harmonics are linear in the profile, so blending them blends profiles
    /// however each node's fit split its profile into lobes; blending their shares of E keeps
    /// that at the ends of the albedo axis too, where E takes its own spline (`albedo_ends`)
    /// that a blend of rμₙ would not follow. 0 at a node where no row holds energy.
    ///
    /// With them, per node of the window, the sharpest lobe of the rows blended there
    /// (`table::node_sharpness` of the slice's rows of nonzero weight, where they hold energy,
    /// each [`ramped`] in by its weight), which [`TableRef::two_lobe_cell`] ramps in by the
    /// nodes' weights along r into the cap of the rebuild.
    pub(super) fn harmonic_shares(
        &self,
        s: &Slice,
        second: &[f32],
        first: usize,
        w: &Weights,
    ) -> Shares {
        // (A table of fewer than 4 radii goes node by node below: a window of 4 would run into
        // the next row.)
        if let Some(shares) = self.shares.filter(|_| self.axes.dims().2 >= 4) {
            let (n_rho, n_theta, n_r) = self.axes.dims();
            // Where every node of the window weighs at least the ramp's weight along r (away
            // from the nodes and the first two intervals), the ramp leaves each node's
            // sharpness whole: the window's precomputed maximum, one read per row, is the cap
            let whole = w.segment() > 1
                && w.as_array()
                    .iter()
                    .all(|x| x.abs() >= f64::from(CAP_RAMP_WEIGHT));
            return Self::blended_shares(s, shares, first, n_rho * n_theta * n_r, whole);
        }
        // sum[n][k]: Σ ω × share n at node k; weight[k]: Σ ω over the rows with energy there.
        // In f32, like the stored values and the GWC window (`TableRef::blend`), and laid out per harmonic so the
        // four nodes of a row update together.
        let (mut sum, mut weight, mut sharpest) = ([[0.0f32; 4]; 4], [0.0f32; 4], [0.0f32; 4]);
        let n = s.len.min(16);
        let (_, _, n_r) = self.axes.dims();
        let mut add = |w: f32, p: &[f32; 12], h: &[f32; 8]| {
            let e: [f32; 4] = std::array::from_fn(|k| p[3 * k]);
            // 1/E where the node holds energy, else 0 (the row adds nothing there)
            let inv = e.map(|e| if e > 0.0 { 1.0 / e } else { 0.0 });
            let share1: [f32; 4] = std::array::from_fn(|k| p[3 * k + 1] * p[3 * k + 2] * inv[k]);
            let shares = [
                share1,
                std::array::from_fn(|k| share1[k] * p[3 * k + 2]),
                std::array::from_fn(|k| h[2 * k] * inv[k]),
                std::array::from_fn(|k| h[2 * k + 1] * inv[k]),
            ];
            for (sum, x) in sum.iter_mut().zip(shares) {
                for k in 0..4 {
                    sum[k] += w * x[k];
                }
            }
            for k in 0..4 {
                weight[k] += if e[k] > 0.0 { w } else { 0.0 };
                if e[k] > 0.0 && w != 0.0 {
                    let cell = [p[3 * k], p[3 * k + 1], p[3 * k + 2], h[2 * k], h[2 * k + 1]];
                    sharpest[k] = sharpest[k].max(ramped(w, node_sharpness(cell, self.rebuild)));
                }
            }
        };
        for (&offset, &w) in s.offsets[..n].iter().zip(&s.weights[..n]) {
            let node = offset as usize + first;
            // The four nodes' values are contiguous in each array: one bounds check per array
            let windows = (n_r >= 4)
                .then(|| {
                    let p = self.params.get(node * PARAMS_PER_NODE..)?;
                    let h = second.get(node * HARMONICS_PER_NODE..)?;
                    Some((p.first_chunk::<12>()?, h.first_chunk::<8>()?))
                })
                .flatten();
            match windows {
                Some((p, h)) => add(w, p, h),
                // Fewer than four radii (or the array's end): node by node, zeros past it
                // (nodes past the axis weigh 0 later)
                None => {
                    let (mut p, mut h) = ([0.0f32; 12], [0.0f32; 8]);
                    for k in 0..4 {
                        let at = node + k;
                        if let (Some(pk), Some(hk)) = (
                            self.params
                                .get(at * PARAMS_PER_NODE..(at + 1) * PARAMS_PER_NODE),
                            second.get(at * HARMONICS_PER_NODE..(at + 1) * HARMONICS_PER_NODE),
                        ) {
                            p[3 * k..3 * k + 3].copy_from_slice(pk);
                            h[2 * k..2 * k + 2].copy_from_slice(hk);
                        }
                    }
                    add(w, &p, &h);
                }
            }
        }
        let shares = std::array::from_fn(|k| {
            if weight[k] != 0.0 {
                std::array::from_fn(|n| f64::from(sum[n][k]) / f64::from(weight[k]))
            } else {
                [0.0; 4]
            }
        });
        Shares { shares, sharpest }
    }

    /// [`TableRef::harmonic_shares`] from the shares the table's owner computed
    /// (`table::harmonic_shares_of`): one blend of the four nodes' five values, in row order
    /// (the sums of [`TableRef::blend`], the same as dividing row by row, so the same bits), and
    /// per node of the window the largest sharpness of the rows with weight, each ramped.
    /// `nodes`: the table's node count; `whole`: every node of the window weighs at least the
    /// ramp's weight along r, so that each node counts whole and the window's maximum serves.
    fn blended_shares(
        s: &Slice,
        shares: &[f32],
        first: usize,
        nodes: usize,
        whole: bool,
    ) -> Shares {
        const WINDOW: usize = 4 * SHARES_PER_NODE;
        let mut acc = [0.0f32; WINDOW];
        let after = shares.get(nodes * SHARES_PER_NODE..).unwrap_or_default();
        let (window_max, own) = after.split_at(nodes.min(after.len()));
        let mut sharpest = [0.0f32; 4];
        for (&offset, &w) in s.offsets[..s.len.min(16)].iter().zip(&s.weights) {
            let node = offset as usize + first;
            if let Some(window) = shares
                .get(node * SHARES_PER_NODE..)
                .and_then(<[f32]>::first_chunk::<WINDOW>)
            {
                axpy20(&mut acc, w, window);
            }
            // The sharpness: the window's maximum (in lane 0), or each of its four nodes (they
            // lie in the row, `table::harmonic_shares_of`) lane by lane, `ramped`'s branch once
            // per row
            if whole {
                if let Some(&x) = window_max.get(node).filter(|_| w != 0.0) {
                    sharpest[0] = sharpest[0].max(ramped(w, x));
                }
            } else if let Some(x) = own.get(node..).and_then(<[f32]>::first_chunk::<4>) {
                if w.abs() >= CAP_RAMP_WEIGHT {
                    max4(&mut sharpest, x);
                } else if w != 0.0 {
                    max4(&mut sharpest, &x.map(|x| ramp_below(w, x)));
                }
            }
        }
        if whole {
            sharpest = [sharpest[0]; 4];
        }
        // Read back from memory: taken lane by lane from registers, the blend above compiles
        // to half-filled vectors (a third more instructions per row, 8 % of an evaluation)
        let acc = std::hint::black_box(acc);
        let blended = std::array::from_fn(|k| {
            let node = &acc[SHARES_PER_NODE * k..SHARES_PER_NODE * (k + 1)];
            let weight = node[SHARES_PER_NODE - 1];
            if weight != 0.0 {
                std::array::from_fn(|n| f64::from(node[n]) / f64::from(weight))
            } else {
                [0.0; 4]
            }
        });
        Shares {
            shares: blended,
            sharpest,
        }
    }

    /// The two-lobe profile of energy `e_per_r` = E/r at `r_eval`, from the first array's window
    /// `acc` (E, E_β, c blended with the slice's weights) and [`TableRef::harmonic_shares`]: the
    /// harmonics' shares of E interpolated along r, times E/r (in the first two intervals the
    /// harmonics μₙ themselves, share × E/r at nodes 1 and 2, on the straight line between them,
    /// as the one-lobe β is there: the ln(1/r) growth of E is isotropic), and the profile of
    /// [`TwoLobe::from_moments_capped`] capped at the sharpest node's concentration, each node's
    /// ramped in by its weight along r.
    pub(super) fn two_lobe_cell(
        &self,
        window: impl FnOnce() -> [f32; 12],
        blended: &Shares,
        first: usize,
        r_eval: f64,
        w: &Weights,
        e_per_r: f64,
    ) -> TwoLobe {
        let shares = &blended.shares;
        // The cap: each node's sharpest lobe ramped in by its weight along r, as the rows' are
        // by theirs, so that it moves on continuously where the window does (at a node, the
        // node it drops has weight 0)
        let cap = |weights: [f64; 4]| {
            let ramped = std::array::from_fn::<f32, 4, _>(|k| {
                ramped(weights[k] as f32, blended.sharpest[k])
            });
            f64::from(ramped.into_iter().fold(0.0f32, f32::max))
        };
        let r_nodes = self.axes.r().as_slice();
        if w.segment() <= 1 && r_nodes[0] == 0.0 {
            let acc = window();
            let node = |k: usize| {
                let e = f64::from(acc[PARAMS_PER_NODE * (k - first)]).max(0.0);
                shares[k - first].map(|x| x * e / r_nodes[k])
            };
            let a = node(1);
            let (b, t) = match r_nodes.get(2) {
                Some(&r2) => (node(2), (r_eval - r_nodes[1]) / (r2 - r_nodes[1])),
                None => (a, 0.0),
            };
            let m = std::array::from_fn(|j| a[j] + t * (b[j] - a[j]));
            // (nodes 1 and 2 on the line between them)
            let mut weights = [0.0; 4];
            weights[1 - first] = 1.0 - t;
            if r_nodes.len() > 2 {
                weights[2 - first] = t;
            }
            return TwoLobe::from_moments_capped(e_per_r, m, cap(weights), self.rebuild);
        }
        let weights = node_weights(first, w);
        let mut share = [0.0; 4];
        for (k, &wk) in weights.iter().enumerate() {
            if wk != 0.0 {
                for (acc, x) in share.iter_mut().zip(shares[k]) {
                    *acc += wk * x;
                }
            }
        }
        let cap = cap(weights);
        TwoLobe::from_moments_capped(e_per_r, share.map(|x| x * e_per_r), cap, self.rebuild)
    }

    /// [`TableRef::eval`] of a table with a second lobe: E/r as a one-lobe table evaluates it
    /// ([`TableRef::cell_from`], refinements along ρ′ and r included), the shape from the
    /// harmonics' shares ([`TableRef::two_lobe_cell`]).
    #[inline(never)]
    pub(super) fn eval_two_lobes(
        &self,
        second: &[f32],
        rho: f64,
        theta: f64,
        r: f64,
        phi: f64,
    ) -> Option<f64> {
        let value = match self.axes.rho.hot_eval_weights(rho) {
            Some(albedo) if self.axes.dims().2 >= 4 => {
                self.two_lobes_hot(second, albedo, rho, theta, r, phi)?
            }
            _ => self.two_lobes_cold(second, rho, theta, r, phi)?,
        };
        if !phi.is_finite() || !self.light_enters(theta) {
            return Some(0.0);
        }
        Some(value)
    }

    /// [`TableRef::eval_two_lobes`] on the quick ρ′ weights: the weights and the slice found
    /// once, E's window blended over the slice ([`TableRef::window`], the sums of
    /// [`TableRef::window_at`] that [`TableRef::cell_at_point`] takes, bit for bit).
    #[inline(always)]
    fn two_lobes_hot(
        &self,
        second: &[f32],
        albedo: AlbedoWeights,
        rho: f64,
        theta: f64,
        r: f64,
        phi: f64,
    ) -> Option<f64> {
        let theta_weights = self.theta_weights(theta)?;
        let Some((r_eval, w)) = self.radius(r) else {
            return Some(0.0);
        };
        let first = self.radial_window(&w);
        let blend = Blend::new(&albedo, rho, theta);
        let s = self.slice_of(&albedo.energy, &theta_weights, blend);
        let acc = self.window(&s, first);
        // E/r as `Cell::profile` takes it (the one lobe's β and c are not needed here)
        let (e, _, _) = self.cell_from::<true>(acc, first, r_eval, &w, blend);
        let e_per_r = (e / r_eval).max(0.0);
        let shares = self.harmonic_shares(&s, second, first, &w);
        Some(
            self.two_lobe_cell(|| acc, &shares, first, r_eval, &w, e_per_r)
                .eval(wrap_phi(phi)),
        )
    }

    /// [`TableRef::eval_two_lobes`] elsewhere (the ends of the ρ′ axis, tables of fewer than 4
    /// radii): E/r from [`TableRef::cell_at_point`], the shares over the samplers' slice.
    #[inline(never)]
    fn two_lobes_cold(
        &self,
        second: &[f32],
        rho: f64,
        theta: f64,
        r: f64,
        phi: f64,
    ) -> Option<f64> {
        let Cell::Profile([e_per_r, ..]) = self.cell_at_point(rho, theta, r)? else {
            return Some(0.0);
        };
        self.with_slice(rho, theta, |s| {
            let Some((r_eval, w)) = self.radius(r) else {
                return 0.0;
            };
            let first = self.radial_window(&w);
            let shares = self.harmonic_shares(s, second, first, &w);
            // The first array's window only in the first two intervals, which read it
            let window = || self.window(s, first);
            self.two_lobe_cell(window, &shares, first, r_eval, &w, e_per_r)
                .eval(wrap_phi(phi))
        })
    }
}

/// m = max(m, x) lane by lane (the values are concentrations, never NaN), packed.
#[inline(always)]
fn max4(m: &mut [f32; 4], x: &[f32; 4]) {
    for k in 0..4 {
        m[k] = if x[k] > m[k] { x[k] } else { m[k] };
    }
}

/// acc += w·x over the 20 lanes of a window of four nodes' shares
/// (`table::harmonic_shares_of`), lane by lane, so that it compiles to packed SIMD instructions
/// (as `blend::axpy12`).
#[inline(always)]
fn axpy20(acc: &mut [f32; 4 * SHARES_PER_NODE], w: f32, x: &[f32; 4 * SHARES_PER_NODE]) {
    for k in 0..4 * SHARES_PER_NODE {
        acc[k] += w * x[k];
    }
}
