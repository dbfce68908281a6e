//! Placing one photon's exits: the sampled models (one exit point, a weight per channel, by
//! one-sample multiple importance sampling over the channels) and the walk (every exit score,
//! in each channel). See the module docs of [`crate::render`] for why these are unbiased.

use super::source::Incidence;
use super::tally::Recorder;
use super::Renderer;
use crate::models::ModelKind;
use crate::pbd::Rule;
use crate::table::{Sample, TableRef};
use crate::walk::rng::{photon_stream, UnitF64, Xoshiro256PlusPlus};
use crate::walk::Component;

impl Renderer {
    /// Traces photon `index` into `rec` (the caller ends the photon).
    pub(super) fn trace_photon(&self, index: u64, rec: &mut Recorder<'_>) {
        let mut rng = photon_stream(self.config.seed, index);
        let inc = self.source.sample(&mut rng);
        rec.reflect(inc.reflected);
        if inc.transmitted() <= 0.0 {
            return;
        }
        match (&self.table, &self.walks) {
            (Some(table), _) => self.place_sampled(table.view(), &mut rng, &inc, rec),
            (None, Some(_)) => self.place_walk(index, &inc, rec),
            (None, None) => rec.lost(),
        }
    }

    /// One exit point drawn from a channel's table density, weighted in every channel.
    fn place_sampled(
        &self,
        table: TableRef<'_>,
        rng: &mut Xoshiro256PlusPlus,
        inc: &Incidence,
        rec: &mut Recorder<'_>,
    ) {
        let t = inc.transmitted();
        let perpendicular = self.config.model == ModelKind::Perpendicular;
        // The incidence the table is looked up at: the θ = 0 slice for the perpendicular model.
        let theta = if perpendicular { 0.0 } else { inc.theta };
        let ch = &self.channels;
        // ρ_eff per channel: fixed when the table is looked up at one incidence.
        let rho_eff = self
            .rho_eff_fixed
            .unwrap_or_else(|| ch.map(|c| table.effective_albedo(c.rho, theta).unwrap_or(0.0)));
        let expected = match self.config.model {
            ModelKind::Table | ModelKind::Perpendicular | ModelKind::WalkTable => {
                rho_eff.map(|e| t * e)
            }
            _ => [0.0; 3],
        };
        rec.expect(expected);
        let active = rho_eff.map(|e| e > 0.0);
        let n_active = active.iter().filter(|&&a| a).count();
        let (u_h, u_r, u_phi) = (rng.next_f64(), rng.next_f64(), rng.next_f64());
        if n_active == 0 {
            return;
        }
        // The hero channel: the ⌊u n⌋-th active one.
        let pick = ((u_h * n_active as f64) as usize).min(n_active - 1);
        let Some(h) = (0..3).filter(|&k| active[k]).nth(pick) else {
            rec.lost();
            return;
        };
        let drawn: Option<Sample> = if perpendicular {
            table.sample_perpendicular(ch[h].rho, u_r, u_phi)
        } else {
            table.sample(ch[h].rho, theta, u_r, u_phi)
        };
        let Some(s) = drawn else {
            rec.lost();
            return;
        };
        // Densities per mm² of each active channel at the point: reduced r scales with σ′t,
        // an area density with σ′t².
        let r_mm = s.r / ch[h].sigma_t_prime;
        let mut pdf = [0.0; 3];
        for k in 0..3 {
            let st = ch[k].sigma_t_prime;
            pdf[k] = if k == h {
                s.pdf * st * st
            } else if active[k] {
                // At θ = 0 the table's profile is flat in φ (c = 0), so this is also the
                // perpendicular model's density (tested).
                st * st * table.pdf(ch[k].rho, theta, st * r_mm, s.phi)
            } else {
                0.0
            };
        }
        let mixture = pdf.iter().sum::<f64>() / n_active as f64;
        if !(mixture > 0.0 && mixture.is_finite()) {
            rec.lost();
            return;
        }
        let mut w = [0.0; 3];
        for c in 0..3 {
            let value = match &self.pbd {
                // PBD's S per mm² at the same point, at the photon's own incidence.
                Some(pbd) => {
                    let st = ch[c].sigma_t_prime;
                    st * st * pbd[c].eval(inc.theta, st * r_mm, s.phi, Rule::Fast)
                }
                None => rho_eff[c] * pdf[c],
            };
            w[c] = t * value / mixture;
        }
        let (x, y) = inc.place(r_mm, s.phi);
        rec.exit(x, y, w, false);
    }

    /// Every exit score of the walk in each channel, from the channel's stream of this photon.
    fn place_walk(&self, index: u64, inc: &Incidence, rec: &mut Recorder<'_>) {
        let Some(walks) = &self.walks else {
            return;
        };
        let t = inc.transmitted();
        for (c, walk) in walks.iter().enumerate() {
            let mut rng = photon_stream(self.channel_seeds[c], index);
            // The walk's lengths are mean free paths 1/σt.
            let mm = 1.0 / self.channels[c].sigma_t;
            let path = walk.trace(inc.theta, &mut rng, |e| {
                let (x, y) = inc.rotate(e.x * mm, e.y * mm);
                rec.exit_channel(c, x, y, t * e.weight, e.component == Component::Single);
            });
            rec.events(path.vertices);
        }
    }
}
