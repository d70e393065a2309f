//! The hierarchy's default shading of its coarse lights, beyond the paper
//! ([`Coarse::Adaptive`](super::Coarse::Adaptive)): each shading point shares a budget of
//! representatives among the coarse lights its query gathers, in proportion to what each
//! brings there unshadowed, and shades again with more where its error may exceed the point
//! bound ([`refine`](super::refine)).
//!
//! ## Where a light's blending weight is taken ([`BlendAt`])
//!
//! Eq. (3) weights a coarse light by `B_ℓ(d)` at its centre's distance `d`. Shaded through its
//! representatives, light `i` then gives `B_ℓ(d_i) Σ_j w_ij I_j f_j(x)` (each input light `j`
//! with its trilinear weight `w_ij`, eqs. 1, 2), while brute force gives each input light its
//! whole `I_j f_j(x)`. The weights of all levels sum to one at every distance, and the
//! trilinear weights of the lights of one level standing for an input light sum to one too, so
//! `Σ_ℓ Σ_i w_ij B_ℓ(‖x − p_j‖) = 1` for every input light `j` — at the input light's own
//! distance. At the centres' distances the sum is only close to one: where `B_ℓ` bends (at
//! `r_{ℓ−1}`, `r_ℓ` and `2 r_ℓ`), lights a cell or more apart weigh one input light with
//! different `B`. That is the hierarchy's smoothing, and at α = 4 on Sponza it is most of the
//! error that no number of samples removes (1.78% of the image, unshadowed, against 0.47%
//! blended per representative, both with every representative).
//!
//! [`BlendAt::Representative`] weights each representative by `B_ℓ` at its own distance
//! instead, and gathers every coarse light that may have an input light inside its level's
//! support ([`LightingGridHierarchy::query_reaching`], as far beyond it as the level's
//! farthest input light from its centre, [`Representatives::max_extent`]; then each light by
//! its own [`extent`](Representatives::extent)). Each input light is then counted exactly
//! once: the estimate is unbiased against brute force over the same VPLs, and its error is
//! the samples' noise alone.
//!
//! ## Sharing the samples
//!
//! The estimate that shares them is unshadowed, isotropic and Lambertian: the light's
//! luminance × the cosine at the point (held above 1/4: a light whose centre is behind the
//! surface may still have representatives in front of it) × the clamped `1/d²` × the blending
//! — at the centre, or, blended per representative, its mean over a cell about the centre
//! (`(B(d − h) + 2 B(d) + B(d + h)) / 4`, held above [`MIN_SHARE_WEIGHT`] so that no light
//! that may give light is never shaded). The budget is `mean` per light whose centre is within
//! its support, so the two ways of blending spend alike. A light wholly behind the point
//! ([`behind`]) gives nothing and takes no share. Shares of one or more are rounded down to a
//! power of two and to what there is; a light owed less than one is shaded with that
//! probability and weighted by its inverse, by systematic roulette over the point's lights
//! ([`roulette`](super::roulette)).

use lgh_core::glam::Vec3;
use lgh_core::random::SplitMix64;
use lgh_core::{
    Blending, Illumination, LghBackend, LightSample, LightingGridHierarchy, QueryError,
    ShadingPoint,
};

use super::resample::{pick_number, How, RayRoulette, MAX_CANDIDATES, PICK_SALT};
use super::roulette::Systematic;
use super::{refine, Drawn, Indirect, Tally, WhichVpl};
use crate::prefetch::prefetch;
use crate::representatives::Representatives;

/// Where a coarse light's blending weight `B_ℓ` is taken when it is shaded through its
/// representatives (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BlendAt {
    /// At the light's centre, as in eq. (3): the hierarchy's smoothing stays in the image
    /// (about 1.8% of Sponza's light at α = 4).
    Centre,
    /// At each representative's own distance, every light that may reach the point gathered:
    /// unbiased against brute force over the same VPLs (beyond the paper).
    #[default]
    Representative,
}

impl BlendAt {
    /// Its name on the command line and in outputs: `centre` or `representative`.
    ///
    /// ```
    /// use lgh_vpl::indirect::BlendAt;
    /// assert_eq!(BlendAt::default().name(), "representative");
    /// assert_eq!(BlendAt::Centre.name(), "centre");
    /// ```
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            BlendAt::Centre => "centre",
            BlendAt::Representative => "representative",
        }
    }
}

/// The least blending weight the sharing estimate gives a light blended per representative:
/// its estimate's mean blending can be 0 while one of its input lights, farther out, still has
/// some, and a light never shaded would bias the image. 0.02 erred least of 0.005, 0.02 and
/// 0.05 on Sponza (2.39%, 2.37%, 2.41% at 0.8 samples a light, `docs/gi.md`'s 53 × 30 runs).
pub const MIN_SHARE_WEIGHT: f32 = 0.02;

/// Whether every VPL that a coarse light, its centre at offset `to` from `point`, of a level
/// of spacing `h`, stands for lies behind the surface at `point` (unit shading `normal`):
/// behind its shading plane or its geometric one, where [`super::facing`] says none of them
/// gives anything. Its VPLs lie within one cell of its grid vertex per axis (eqs. 1, 2), and
/// so does its centre (their weighted mean, eq. 3): each is within `2h` of the centre per
/// axis, so a plane that has the centre's whole box of half-width `2h` behind it has them all.
/// Such a light is left out of the sharing — exactly, its share of the estimate is zero — and
/// its representatives are never read.
#[must_use]
fn behind(point: &ShadingPoint, normal: Vec3, to: Vec3, h: f32) -> bool {
    // A hair wider than 2h: the centre and the planes are rounded to f32.
    let reach = 2.0 * h * (1.0 + 1e-5);
    let behind_plane = |n: Vec3| n.dot(to) + reach * n.abs().element_sum() < 0.0;
    behind_plane(normal) || point.geometric.is_some_and(behind_plane)
}

/// How many shaded lights ahead [`Pass::hint`] hints a light's representatives (and half as
/// many, its next draw's VPLs). With one VPL a draw, 16 measured 6–12% faster on Sponza than
/// no hints; with four candidates a draw, 4 measured 7% faster than 16 (three alternating
/// pairs), 2 no faster, 8 no different (seven pairs).
const HINT_AHEAD: usize = 4;

/// The salt of the roulette's sequence at a shading point (the area lights' patterns use the
/// triangle's index, which stays below 2³²).
const ROULETTE_SALT: u64 = 0xada << 40;

/// A coarse light gathered at a point, as the passes over them read it: compact, for the
/// thousands a point gathers.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    /// Its roulette number at this point, drawn at the first pass.
    u: f64,
    /// Its index in its level.
    index: u32,
    /// Its level (≥ 1).
    level: u8,
    /// Draws shaded so far (0: none — skipped by the roulette, or not yet seen); their
    /// estimate is `done[slot]`.
    m: u8,
    /// The candidates of each of its `m` draws (1: each a representative of its own;
    /// [`resample`](super::resample)).
    g: u8,
    /// Where its estimate is kept, once it has one.
    slot: u32,
    /// The luminance its representatives share ([`Drawn::luminance`]).
    luminance: f32,
    /// The blending its isotropic point is taken at for the variance's which-VPL term: `B_ℓ`
    /// at the centre, or the sharing estimate's mean.
    weight: f32,
    /// The unshadowed estimate that shares the samples.
    share: f32,
}

/// A coarse light's estimate through the first `m` of its representatives, unweighted (by
/// the roulette too), kept from one pass to the next at a point: the next pass's longer
/// prefix starts with them.
#[derive(Clone, Copy, Debug, Default)]
struct Estimate {
    radiance: Vec3,
    tally: Tally,
    /// A single resampled draw's which-VPL variance ([`Draw::spread`](super::resample::Draw::spread)); else 0.
    spread: f64,
    /// A single resampled draw's ray roulette variance ([`Draw::played`](super::resample::Draw::played)); else 0.
    played: f64,
}

/// A point's gathered lights and their estimates, reused from point to point on a thread.
#[derive(Default)]
struct Scratch {
    lights: Vec<Candidate>,
    done: Vec<Estimate>,
    /// A pass's shaded lights: index in `lights`, and share.
    chosen: Vec<(u32, f32)>,
}

/// What `point` receives through `backend` with [`Coarse::Adaptive`](super::Coarse): level 0
/// exactly, the coarse lights through a share of `mean` samples each, blended as `blend`
/// says, shaded again with more while the estimate's error may exceed the shader's point
/// bound ([`refine`](super::refine)); and whether they were.
pub(super) fn adaptive(
    point: &ShadingPoint,
    backend: &LghBackend<'_>,
    reps: &Representatives,
    mean: f32,
    blend: BlendAt,
    candidates: u32,
    shader: &Indirect<'_>,
) -> Result<(Illumination, bool), QueryError> {
    thread_local! {
        static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
    }
    let Some(normal) = point.normal else {
        let dark = Illumination {
            radiance: Vec3::ZERO,
            lights: 0,
        };
        return Ok((dark, false));
    };
    SCRATCH.with_borrow_mut(|scratch| {
        scratch.lights.clear();
        scratch.done.clear();
        let (mut radiance, lights, nominal) = gather(
            point,
            normal,
            backend,
            reps,
            blend,
            shader,
            &mut scratch.lights,
        )?;
        let blending = (blend == BlendAt::Representative).then(|| backend.blending());
        let mut rng = SplitMix64(crate::direct::point_seed(point.position, ROULETTE_SALT));
        let pass = Pass {
            lgh: backend.hierarchy(),
            point,
            normal,
            reps,
            blending,
            shader,
            nominal,
            total: scratch.lights.iter().map(|c| c.share).sum(),
            candidates: candidates.clamp(1, MAX_CANDIDATES) as usize,
            seed: crate::direct::point_seed(point.position, PICK_SALT),
            rays: std::cell::Cell::default(),
        };
        let mut mean = mean;
        let mut result = pass.run(scratch, mean, Some(rng.next_f64()));
        let mut rounds = 0;
        if let Some(bound) = shader.settings.point_error {
            while rounds < refine::MAX_ROUNDS
                && !result.complete
                && refine::needs_refining(
                    f64::from(lgh_core::luminance(radiance + result.radiance)),
                    result.variance,
                    bound,
                )
            {
                mean *= refine::GROWTH;
                result = pass.run(scratch, mean, None);
                rounds += 1;
            }
        }
        radiance += result.radiance;
        Ok((Illumination { radiance, lights }, rounds > 0))
    })
}

/// The query at `point` (unit shading `normal`): level 0 shaded exactly, its radiance
/// returned, and the coarse lights that may give light — not [`behind`] the point, and not
/// facing away from it ([`crate::facing`]) — pushed on `out` with their sharing estimates;
/// with the number of lights gathered and the budget's count: the lights not behind the
/// point whose centre is within its level's support, those facing away included (their
/// share of the budget goes to the others).
fn gather(
    point: &ShadingPoint,
    normal: Vec3,
    backend: &LghBackend<'_>,
    reps: &Representatives,
    blend: BlendAt,
    shader: &Indirect<'_>,
    out: &mut Vec<Candidate>,
) -> Result<(Vec3, u32, usize), QueryError> {
    let lgh = backend.hierarchy();
    let h0 = shader.settings.h0;
    let x = point.position;
    let blending = backend.blending();
    let mut radiance = Vec3::ZERO;
    let mut level0 = |s: &LightSample| {
        let vpl = lgh.input_index(s.index);
        radiance += shader.shade(point, s, vpl);
    };
    // The cosine at the point, held above 1/4 (module docs), towards offset `to` at `d`.
    let cosine = |to: Vec3, d: f32| {
        if d > 0.0 {
            normal.dot(to / d).max(0.25)
        } else {
            1.0
        }
    };
    // Whether every VPL the light at `d` stands for faces away from the point
    // ([`crate::facing`]).
    let away = |level: u8, index: u32, d: f32| {
        let extent = reps.extent(level, index);
        reps.facing(level, index).faces_away(x, d, extent)
    };
    // The lights the budget counts that face away.
    let mut turned = 0;
    let candidate = |level: u8, index: u32, luminance: f32, weight: f32, share: f32| Candidate {
        u: 0.0,
        index,
        level,
        m: 0,
        g: 0,
        slot: 0,
        luminance,
        weight,
        share,
    };
    match blend {
        BlendAt::Centre => {
            let lights = lgh.query(x, blending, |s| {
                if s.level == 0 {
                    return level0(s);
                }
                let to = s.position - x;
                let d = to.length();
                let luminance = lgh_core::luminance(s.intensity);
                if behind(point, normal, to, lgh.h(s.level)) {
                    return;
                }
                if away(s.level, s.index, d) {
                    turned += 1;
                    return;
                }
                let share = luminance * cosine(to, d) * lgh_core::falloff(d, h0);
                out.push(candidate(s.level, s.index, luminance, s.weight, share));
            })?;
            Ok((radiance, lights, out.len() + turned))
        }
        BlendAt::Representative => {
            let mut lights = lgh.query_levels(x, blending, 0..=0, &mut level0)?;
            let mut nominal = 0;
            let extents = |l| (reps.max_extent(l), reps.extents(l));
            lights += lgh.query_reaching(x, blending, extents, |r| {
                let level = lgh.level(r.level);
                let (i, d) = (r.index as usize, r.distance);
                let to = level.position(i) - x;
                let h = lgh.h(r.level);
                if behind(point, normal, to, h) {
                    return;
                }
                nominal += usize::from(r.weight > 0.0);
                if away(r.level, r.index, d) {
                    return;
                }
                let b = |d: f32| blending.weight(r.level, d.max(0.0));
                let weight = ((b(d - h) + 2.0 * r.weight + b(d + h)) * 0.25).max(MIN_SHARE_WEIGHT);
                let luminance = level.luminance(i);
                let share = luminance * weight * cosine(to, d) * lgh_core::falloff(d, h0);
                out.push(candidate(r.level, r.index, luminance, weight, share));
            })?;
            Ok((radiance, lights, nominal))
        }
    }
}

/// One pass's result ([`Pass::run`]).
struct PassResult {
    /// What the coarse lights give.
    radiance: Vec3,
    /// Its estimated variance in luminance ([`refine`](super::refine)); 0 where the shader has
    /// no point bound, which is the only reader.
    variance: f64,
    /// Whether every light was shaded through all its representatives, unweighted: more
    /// samples cannot change the estimate.
    complete: bool,
}

/// A light's estimate in one pass ([`Pass::shade_light`]).
struct Shaded {
    /// Its estimate through its prefix, unweighted by the roulette.
    estimate: Estimate,
    /// The roulette's probability of shading it (1 for a light owed a draw or more).
    p: f64,
    /// Whether its draws are resampled (two candidates or more each).
    resampled: bool,
    /// Whether it was shaded through all its representatives, unweighted.
    complete: bool,
}

/// The draws of one light in a pass ([`Pass::shade_draws`]).
struct Draws<'r> {
    /// Its level (≥ 1) and index there.
    level: u8,
    index: u32,
    /// Its representatives, nested.
    all: &'r [u32],
    /// The candidates of each draw (1: each draw one representative).
    g: usize,
    /// The light as its representatives are shaded.
    drawn: Drawn<'r>,
}

impl Draws<'_> {
    /// Whether each draw is resampled among two candidates or more.
    fn resampled(&self) -> bool {
        self.g >= 2
    }
}

/// The parts of a pass's variance in luminance, summed over its lights
/// ([`Pass::add_variance`]).
#[derive(Default)]
struct Variance {
    /// The lights' own (k ≥ 2) and the roulettes'.
    own: f64,
    /// The unshadowed squares of the single draws, whose visibility is taken at the point's
    /// fraction.
    single_sq: f64,
    /// The draws' luminance, shadowed and unshadowed: the point's visible fraction.
    lit: f64,
    unshadowed: f64,
    /// Which VPL the single draws drew, fitted over all of them (`WhichVpl`).
    which: WhichVpl,
}

impl Variance {
    /// The pass's variance.
    fn total(self) -> f64 {
        let own = self.own + self.which.variance();
        let visible = if self.unshadowed > 0.0 {
            self.lit / self.unshadowed
        } else {
            1.0
        };
        own + visible * (1.0 - visible) * self.single_sq
    }
}

/// The passes over one point's coarse lights.
struct Pass<'a> {
    lgh: &'a LightingGridHierarchy,
    point: &'a ShadingPoint,
    normal: Vec3,
    reps: &'a Representatives,
    /// With each representative blended at its own distance: the blending.
    blending: Option<&'a Blending>,
    shader: &'a Indirect<'a>,
    /// The lights the budget counts.
    nominal: usize,
    /// The sum of the lights' shares (the same every pass).
    total: f32,
    /// The candidates of a resampled draw (1: each draw is a representative of its own).
    candidates: usize,
    /// The point's seed for the resampled draws' picks.
    seed: u64,
    /// The roulette on the resampled draws' shadow rays, over every pass at the point.
    rays: std::cell::Cell<RayRoulette>,
}

impl Pass<'_> {
    /// One pass over the point's lights in `scratch`: `mean` samples per counted light shared
    /// in proportion to the estimates, the roulette's numbers drawn from `offset` at the first
    /// pass (`Some`) and kept after. A light that takes more draws than before shades only
    /// the draws it had not (the prefixes are nested, so this is the same estimate as shading
    /// them all, with fewer shadow rays); its draws keep the candidates they had, and past its
    /// representatives they wrap around ([`draw_candidates`]).
    fn run(&self, scratch: &mut Scratch, mean: f32, offset: Option<f64>) -> PassResult {
        let Scratch {
            lights,
            done,
            chosen,
        } = scratch;
        let mut complete = self.choose(lights, chosen, mean, offset);
        let mut radiance = Vec3::ZERO;
        // Without a point bound nothing reads the variance: its parts are not computed.
        let estimate_variance = self.shader.settings.point_error.is_some();
        let mut variance = Variance::default();
        for (k, &(i, want)) in chosen.iter().enumerate() {
            self.hint(lights, chosen, k);
            let light = &mut lights[i as usize];
            let shaded = self.shade_light(light, done, want);
            complete &= shaded.complete;
            radiance += shaded.estimate.radiance * (1.0 / shaded.p) as f32;
            if estimate_variance {
                self.add_variance(&mut variance, light, &shaded);
            }
        }
        PassResult {
            radiance,
            variance: variance.total(),
            complete,
        }
    }

    /// The lights of this pass, pushed on `chosen` (cleared first) with the draws each is
    /// owed of `mean` per counted light: every light, but those the roulette leaves out
    /// (its numbers drawn from `offset` at the first pass, kept in the lights after). Their
    /// representatives are hinted to the cache as they are chosen. Returns whether no light
    /// was left out.
    fn choose(
        &self,
        lights: &mut [Candidate],
        chosen: &mut Vec<(u32, f32)>,
        mean: f32,
        offset: Option<f64>,
    ) -> bool {
        let total = self.total;
        // At least one light's worth: a point whose every light is gathered by its extent
        // alone (its centre outside the support) would otherwise get no samples and lose the
        // light those lights' VPLs give it. Each light's share is above zero, so with any
        // budget every light may be shaded.
        let budget = mean.max(0.0) * self.nominal.max(1) as f32;
        let nested = self.reps.is_nested();
        let mut complete = true;
        // The lights shaded this pass, with their shares: chosen first, so that their
        // representatives and VPLs can be hinted to the cache a few lights ahead.
        chosen.clear();
        let mut roulette = offset.map(Systematic::new);
        for (i, light) in lights.iter_mut().enumerate() {
            let want = if total > 0.0 {
                budget * light.share / total
            } else {
                1.0
            };
            // Systematic over the point's lights, drawn once per light and point: a later
            // pass, whose `want` is larger, keeps every light this one shaded (the roulettes
            // are coupled), and their shadow rays.
            if let Some(r) = roulette.as_mut() {
                light.u = r.next(f64::from(want));
            }
            if nested && want < 1.0 && light.u >= f64::from(want) {
                // Left out by the roulette, before its representatives are looked up.
                complete = false;
                continue;
            }
            // Where its representatives are, hinted now: the light is shaded a few hundred
            // lights later (0.95x the time on Sponza, nine alternating pairs).
            self.reps.hint(light.level, light.index);
            chosen.push((i as u32, want));
        }
        complete
    }

    /// `light`, owed `want` draws, shaded through a prefix of its representatives: its
    /// estimate, kept in `done` (the draws it had before kept, only the new ones shaded), and
    /// its draws and their candidates noted in `light`.
    fn shade_light(&self, light: &mut Candidate, done: &mut Vec<Estimate>, want: f32) -> Shaded {
        let nested = self.reps.is_nested();
        let all = self.reps.of(light.level, light.index);
        let (m, p) = prefix(nested, want, all.len());
        // Resampled draws of `g` candidates each. A fresh light's draws look at fewer
        // candidates the more of them it takes, down to every representative with a ray
        // of its own (the estimate complete); a light shaded before keeps its draws'
        // candidates, so that the new draws add to the old (shading it afresh with fewer
        // threw 15% of the draws away on Sponza; keeping them took 0.97x the time at the
        // same error over ten alternating pairs).
        let g = if !nested {
            1
        } else if light.m > 0 {
            usize::from(light.g)
        } else {
            group(self.candidates, all.len(), m)
        };
        let draws = Draws {
            level: light.level,
            index: light.index,
            all,
            g,
            drawn: Drawn {
                luminance: light.luminance,
                blend: self.blending.map(|b| (b, light.level)),
            },
        };
        // Every draw the light can take (resampled draws past its representatives wrap
        // around, so a light drawn with `g ≥ 2` takes at most as many as it has).
        let complete = m >= all.len() && p == 1.0;
        // The draws shaded before (of `g` candidates too).
        let before = usize::from(light.m);
        let estimate = if before == m {
            // The same draws as before: the same estimate.
            done[light.slot as usize]
        } else if before > 0 && before < m {
            // The first `before` as before; the rest shaded now; both at their share of m.
            let mut rest = Tally::default();
            let (a, b) = (before as f32 / m as f32, (m - before) as f32 / m as f32);
            let (more, _, _) = self.shade_draws(&draws, before..m, &mut rest, b / p as f32);
            let kept = done[light.slot as usize];
            let tally = kept
                .tally
                .scaled(f64::from(a))
                .merged(&rest.scaled(f64::from(b)));
            Estimate {
                radiance: kept.radiance * a + more * b,
                tally,
                spread: 0.0,
                played: 0.0,
            }
        } else {
            let mut tally = Tally::default();
            let (radiance, spread, played) =
                self.shade_draws(&draws, 0..m, &mut tally, 1.0 / p as f32);
            Estimate {
                radiance,
                tally,
                spread,
                played,
            }
        };
        if light.m == 0 {
            light.slot = done.len() as u32;
            done.push(estimate);
        } else {
            done[light.slot as usize] = estimate;
        }
        light.g = g as u8;
        // At most 64 representatives a light (`MAX_PER_LIGHT`).
        light.m = m.min(usize::from(u8::MAX)) as u8;
        Shaded {
            estimate,
            p,
            resampled: draws.resampled(),
            complete,
        }
    }

    /// Draws `range` of a light, shaded now, with the light's luminance over `range.len()`,
    /// each added to `tally`; `at_point` is the fraction of the point's light a draw stands
    /// for, which its ray's roulette plays with ([`RayRoulette`]). With a single resampled
    /// draw, also its which-VPL and ray roulette variances ([`Draw`](super::resample::Draw)); else 0 and 0.
    fn shade_draws(
        &self,
        draws: &Draws<'_>,
        range: std::ops::Range<usize>,
        tally: &mut Tally,
        at_point: f32,
    ) -> (Vec3, f64, f64) {
        let (point, normal, shader) = (self.point, self.normal, self.shader);
        if !draws.resampled() {
            let ids = draws
                .all
                .get(range)
                .unwrap_or(&[])
                .iter()
                .map(|&i| i as usize);
            let lit = shader.shade_drawn(point, normal, draws.drawn, ids, tally);
            return (lit, 0.0, 0.0);
        }
        // Each draw with the light's luminance over the draws shaded now.
        let each = Drawn {
            luminance: draws.drawn.luminance / range.len() as f32,
            ..draws.drawn
        };
        let single = range.len() == 1;
        let (mut radiance, mut spread, mut played) = (Vec3::ZERO, 0.0, 0.0);
        let mut rays = self.rays.get();
        for s in range {
            let how = How {
                numbers: pick_number(self.seed, draws.level, draws.index, s),
                at_point,
                rays: &mut rays,
            };
            let them = draw_candidates(draws.all, draws.g, s);
            let draw = shader.shade_resampled(point, normal, each, them, how, tally);
            radiance += draw.lit;
            if single {
                (spread, played) = (draw.spread, draw.played);
            }
        }
        self.rays.set(rays);
        (radiance, spread, played)
    }

    /// Adds `light`'s part of the pass's variance, from its estimate `shaded`
    /// ([`refine`](super::refine)).
    fn add_variance(&self, parts: &mut Variance, light: &Candidate, shaded: &Shaded) {
        let (point, normal, p) = (self.point, self.normal, shaded.p);
        let estimate = &shaded.estimate;
        let tally = estimate.tally;
        parts.lit += tally.lit();
        parts.unshadowed += tally.unshadowed();
        let scale = 1.0 / (p * p);
        if tally.draws() >= 2 {
            parts.own += tally.variance(0.0) * scale;
        } else {
            parts.single_sq += tally.unshadowed_squares() * scale;
            // Its ray's roulette (the sample variance of two or more draws has it).
            parts.own += estimate.played * scale;
            if shaded.resampled && tally.unshadowed() > 0.0 {
                // Which VPL was drawn, from the spread of the draw's own candidates. (A
                // draw whose every candidate is dark says nothing of the light's other
                // representatives: the fit below.)
                parts.own += estimate.spread * scale;
            } else {
                // Which VPL was drawn: its unshadowed share against the light's own,
                // unshadowed, as the isotropic point it is in the hierarchy, scaled by
                // the factor that fits the point's single draws best (one draw's
                // deviation from the mean it estimates, `refine::WhichVpl`).
                let level = self.lgh.level(light.level);
                let (position, intensity) = (
                    level.position(light.index as usize),
                    level.intensity(light.index as usize) * light.weight,
                );
                let point_like = if super::facing(point, normal, position) {
                    let lit = self.shader.reflect(point, normal, position, intensity);
                    f64::from(lgh_core::luminance(lit))
                } else {
                    0.0
                };
                parts.which.add(tally.unshadowed(), point_like, scale);
            }
        }
        if p < 1.0 {
            let x = tally.lit() / p;
            parts.own += x * x * (1.0 - p);
        }
    }

    /// Hints to the cache what the `k`-th chosen light's successors will read: the
    /// representatives of the one [`HINT_AHEAD`] lights ahead, and the next VPLs to shade of
    /// the one half as far (whose representatives were hinted before).
    #[inline(always)]
    fn hint(&self, lights: &[Candidate], chosen: &[(u32, f32)], k: usize) {
        let light = |k: usize| chosen.get(k).and_then(|&(i, _)| lights.get(i as usize));
        if let Some(l) = light(k + HINT_AHEAD) {
            if let Some(first) = self.reps.of(l.level, l.index).first() {
                prefetch(first);
            }
        }
        if let Some(l) = light(k + HINT_AHEAD / 2) {
            // Its next draw's VPLs: the next representative, or the next resampled draw's
            // candidates.
            let all = self.reps.of(l.level, l.index);
            // (A plain light's next few, up to `candidates`: its draws may grow by as many.)
            let next = (usize::from(l.m) * usize::from(l.g.max(1))) % all.len().max(1);
            for &j in all.iter().skip(next).take(self.candidates) {
                if let Some(v) = self.shader.vpls.get(j as usize) {
                    prefetch(v);
                }
            }
        }
    }
}

/// The candidates of a light's resampled draw `s` among its nested representatives `all`,
/// `g` of them (a power of two, at most `all.len()`): the `s`-th run of `g`, wrapping around
/// past the end. `m` draws, `m` a power of two, look at a power-of-two prefix of the
/// representatives; past `all.len() / g` draws, at every run alike, `m g / all.len()` draws
/// each (each draw's pick its own). Either way their mean is unbiased
/// ([`resample`](super::resample)).
#[inline]
#[must_use]
fn draw_candidates(all: &[u32], g: usize, s: usize) -> &[u32] {
    let runs = (all.len() / g.max(1)).max(1);
    let k = s % runs;
    all.get(k * g..(k + 1) * g).unwrap_or(&[])
}

/// The candidates of each of `m` resampled draws of a light of `len` nested representatives,
/// at most `candidates`: the largest power of two that lets the draws look at a power-of-two
/// prefix, `m G ≤ len` (1: each draw a representative of its own).
#[inline]
#[must_use]
fn group(candidates: usize, len: usize, m: usize) -> usize {
    let most = candidates.min(len / m.max(1)).max(1);
    1 << most.ilog2()
}

/// A light's prefix of `len` representatives owed `want` samples, and the probability it is
/// shaded with: with nested representatives, the largest power of two not above `want` nor
/// above what there is, or one kept by the roulette with probability `want` below one; else
/// all of them.
#[inline]
#[must_use]
fn prefix(nested: bool, want: f32, len: usize) -> (usize, f64) {
    if !nested {
        (len, 1.0)
    } else if want >= 1.0 {
        let m = (want as usize).clamp(1, len.max(1));
        let m = if m.is_power_of_two() {
            m
        } else {
            m.next_power_of_two() / 2
        };
        (m, 1.0)
    } else {
        (1, f64::from(want))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::indirect::tests::{light_sum, pool, rel_rmse, Fixture};
    use crate::indirect::{render_lgh, Coarse};
    use crate::render::Rendered;
    use crate::representatives::Allocation;

    /// The per-representative blending counts every VPL exactly once: at each point the
    /// camera sees in the room (α = 4), every VPL's weight — `B_0` at its distance if level 0
    /// gathers it, plus `w_ij B_ℓ(‖x − p_j‖)` for every coarse light `i` that
    /// [`LightingGridHierarchy::query_reaching`] finds with the representatives' extents and
    /// that stands for it — sums to one (to 1e-5: f32 weights, f64 sums). Blended at the
    /// centres (eq. 3) the sums stray (by up to 0.26 here), and blended per VPL over eq. (3)'s
    /// lights alone they fall short where a light's centre is outside its support but some of
    /// its VPLs are inside: both checks bite.
    #[test]
    fn blending_at_each_representative_counts_every_vpl_once() {
        let f = Fixture::new();
        let reps = Representatives::build_with(&f.lgh, Allocation::Nested(4));
        let blending = f.lgh.blending(4.0).unwrap();
        let lit: Vec<bool> = f.vpls.iter().map(|v| v.power.max_element() > 0.0).collect();
        let (mut worst_centre, mut worst_nominal) = (0.0f64, 0.0f64);
        let mut points = 0;
        for (point, _) in f.seen(12, 9) {
            points += 1;
            let x = point.position;
            let own = |j: usize| (x - f.vpls[j].position).length();
            // Per VPL: the per-representative sum, the centre-blended one, and the
            // per-representative one over eq. (3)'s lights only.
            let n = f.vpls.len();
            let (mut each, mut centre, mut nominal) =
                (vec![0.0f64; n], vec![0.0f64; n], vec![0.0f64; n]);
            f.lgh
                .query_levels(x, &blending, 0..=0, |s| {
                    let j = f.lgh.input_index(s.index).unwrap();
                    let w = f64::from(blending.weight(0, own(j)));
                    each[j] += w;
                    centre[j] += f64::from(s.weight);
                    nominal[j] += w;
                })
                .unwrap();
            let extents = |l| (reps.max_extent(l), reps.extents(l));
            f.lgh
                .query_reaching(x, &blending, extents, |r| {
                    crate::representatives::contributors(&f.lgh, r.level, r.index, |j, w, _| {
                        let b = f64::from(blending.weight(r.level, own(j)));
                        each[j] += w * b;
                        centre[j] += w * f64::from(r.weight);
                        if r.weight > 0.0 {
                            nominal[j] += w * b;
                        }
                    });
                })
                .unwrap();
            for j in (0..n).filter(|&j| lit[j]) {
                assert!((each[j] - 1.0).abs() < 1e-5, "VPL {j} at {x}: {}", each[j]);
                worst_centre = worst_centre.max((centre[j] - 1.0).abs());
                worst_nominal = worst_nominal.max((1.0 - nominal[j]).abs());
            }
        }
        println!("{points} points; centre-blended sums off by up to {worst_centre:.4}, eq. (3)'s lights alone {worst_nominal:.4}");
        assert!(points > 50);
        assert!(worst_centre > 0.01, "{worst_centre}");
        assert!(worst_nominal > 0.01, "{worst_nominal}");
    }

    /// Blended at each representative, the hierarchy's estimate is brute force's, up to the
    /// representatives' noise: in the room at α = 4 without shadow rays (so only the blending
    /// and the draws differ from brute force), every coarse light through all 32 of its
    /// representatives. Measured: 0.38% against brute force where eq. (3)'s centre blending
    /// leaves 1.95% (the hierarchy's smoothing); the image's mean 1.0024 times brute force's
    /// (centre: 1.0083). Asserted: under half the centre's error, the mean within 0.5% (the
    /// representatives are a fixed systematic sample of each light's VPLs: their noise over
    /// 768 pixels that share lights, a few tenths of a percent). And with `lgh gi`'s defaults
    /// (0.35 draws a light resampled among 4, the ray roulette, the lights facing away left
    /// out, the 10% point bound, shadows) the image is the same on 1 and 3 threads.
    #[test]
    fn blending_at_each_representative_leaves_only_the_draws_noise() {
        let f = Fixture::new();
        let reps = Representatives::build_with(&f.lgh, Allocation::Nested(32));
        let camera = Fixture::camera(32, 24);
        let shader = f.unshadowed_shader();
        let exact = f.exact(&shader, &camera);
        let backend = LghBackend::new(&f.lgh, 4.0).unwrap();
        let render = |blend| {
            let coarse = Coarse::Adaptive {
                reps: &reps,
                mean: 64.0,
                blend,
                candidates: 1,
            };
            render_lgh(&f.scene, &camera, &backend, coarse, &shader, |_| {}).unwrap()
        };
        let (each, centre) = (render(BlendAt::Representative), render(BlendAt::Centre));
        let (e, c) = (rel_rmse(&each, &exact), rel_rmse(&centre, &exact));
        let (m, mc) = (
            light_sum(&each) / light_sum(&exact),
            light_sum(&centre) / light_sum(&exact),
        );
        println!("per representative {e:.4} (mean {m:.4}), centre {c:.4} (mean {mc:.4})");
        assert!(e < 0.5 * c, "{e} against {c}");
        assert!((m - 1.0).abs() < 0.005, "{m}");
        let shader = Indirect::new(
            &f.scene,
            &f.vpls,
            super::super::IndirectSettings {
                point_error: Some(super::super::refine::DEFAULT_POINT_ERROR),
                ..f.shader().settings
            },
        );
        // As `lgh gi` builds them: summarised, so that lights facing away are left out.
        let reps = Representatives::build_for(&f.lgh, Allocation::Nested(32), &f.vpls);
        let render = || {
            let coarse = Coarse::Adaptive {
                reps: &reps,
                mean: crate::gi::DEFAULT_ADAPTIVE_SAMPLES,
                blend: BlendAt::Representative,
                candidates: super::super::resample::DEFAULT_CANDIDATES,
            };
            render_lgh(&f.scene, &camera, &backend, coarse, &shader, |_| {}).unwrap()
        };
        assert_eq!(pool(1).install(render), pool(3).install(render));
    }

    /// Lights that face away from a point ([`crate::facing`]) are left out of it and nothing
    /// is lost: in the room at α = 4 without shadow rays, every coarse light shaded through
    /// all 32 of its representatives, one ray each (so the estimate is the same whatever the
    /// budget), the
    /// image with the lights summarised ([`Representatives::build_for`]) against the one
    /// without — every pixel within 1e-5 of the brighter's light, the grazing light the test
    /// may drop (`facing`'s module docs) and f32 sums. Measured first: a share of the lights
    /// each point gathers, and does not leave out as [`behind`] it, faces away (asserted:
    /// more than 5%), so the comparison bites.
    /// At `lgh gi`'s default 0.35 draws a light, with shadow rays, the image's mean is that of
    /// the complete image: measured 0.9983 of it; asserted within 0.75% — the estimator's own
    /// deviation on these small images is 0.17% here and 0.49% in `resample`'s test of the
    /// same room, so a bias of 1% fails.
    #[test]
    fn lights_facing_away_are_left_out_and_nothing_is_lost() {
        let f = Fixture::new();
        let summarised = Representatives::build_for(&f.lgh, Allocation::Nested(32), &f.vpls);
        // The same draws, without the summaries.
        let strata: Vec<u8> = f.vpls.iter().map(crate::vpl::Vpl::orientation).collect();
        let plain = Representatives::build_stratified(&f.lgh, Allocation::Nested(32), &strata);
        let camera = Fixture::camera(24, 18);
        let shader = f.unshadowed_shader();
        let backend = LghBackend::new(&f.lgh, 4.0).unwrap();
        // The share of the gathered lights that face away, over the points the camera sees:
        // those the gather keeps without the summaries and leaves out with them.
        let (mut gathered, mut away) = (0usize, 0usize);
        let mut out = Vec::new();
        for (point, normal) in f.seen(24, 18) {
            let mut kept = |reps: &Representatives| {
                out.clear();
                let blend = BlendAt::Representative;
                gather(&point, normal, &backend, reps, blend, &shader, &mut out).unwrap();
                out.len()
            };
            let (all, facing) = (kept(&plain), kept(&summarised));
            gathered += all;
            away += all - facing;
        }
        println!("{away} of {gathered} gathered lights not behind the points face away");
        assert!(away * 20 > gathered, "{away} of {gathered}");
        let render = |reps: &Representatives, mean: f32, shader: &Indirect<'_>| {
            let coarse = Coarse::Adaptive {
                reps,
                mean,
                blend: BlendAt::Representative,
                // Complete estimates need plain draws; the sampled one takes the default.
                candidates: if mean > 64.0 {
                    1
                } else {
                    super::super::resample::DEFAULT_CANDIDATES
                },
            };
            render_lgh(&f.scene, &camera, &backend, coarse, shader, |_| {}).unwrap()
        };
        // A budget no light's share falls short of all its representatives in.
        let all = 1e6;
        let (with, without) = (
            render(&summarised, all, &shader),
            render(&plain, all, &shader),
        );
        for (a, b) in with.image.pixels.iter().zip(&without.image.pixels) {
            let scale = a.max_element().max(b.max_element());
            assert!(
                (*a - *b).abs().max_element() <= 1e-5 * scale,
                "{a} against {b}"
            );
        }
        let shadowed = f.shader();
        let mean = crate::gi::DEFAULT_ADAPTIVE_SAMPLES;
        let (sampled, complete) = (
            render(&summarised, mean, &shadowed),
            render(&summarised, all, &shadowed),
        );
        let ratio = light_sum(&sampled) / light_sum(&complete);
        println!("mean at {mean} draws a light: {ratio:.4} of the complete image's");
        assert!((ratio - 1.0).abs() < 0.0075, "{ratio}");
    }

    /// A light's resampled draws look at a power-of-two prefix of its representatives,
    /// fewer candidates each as the draws grow, down to one.
    #[test]
    fn draws_look_at_fewer_candidates_as_they_grow() {
        let g = |m| group(4, 32, m);
        assert_eq!([1, 2, 4, 8, 16, 32].map(g), [4, 4, 4, 4, 2, 1]);
        for m in [1, 2, 4, 8, 16, 32] {
            assert!(m * g(m) <= 32 && (m * g(m)).is_power_of_two());
        }
        // Short lights, none, and one candidate.
        assert_eq!(group(4, 2, 1), 2);
        assert_eq!(group(4, 0, 1), 1);
        assert_eq!(group(1, 32, 1), 1);
        assert_eq!(group(16, 32, 1), 16);
    }

    /// A light's draws past its representatives wrap around: `m` draws of `g` candidates
    /// look at a power-of-two prefix while `m g ≤ len`, and past it at every run of `g` alike,
    /// `m g / len` times each — so their mean weighs every representative alike, and stays
    /// unbiased.
    #[test]
    fn draws_past_the_representatives_wrap_around() {
        let all: Vec<u32> = (100..132).collect();
        for g in [1, 2, 4, 8, 16] {
            for m in [1, 2, 4, 8, 16, 32, 64] {
                let mut seen = vec![0usize; all.len()];
                for s in 0..m {
                    let them = draw_candidates(&all, g, s);
                    assert_eq!(them.len(), g);
                    for &j in them {
                        seen[(j - 100) as usize] += 1;
                    }
                }
                let looked: Vec<usize> = seen.iter().copied().filter(|&c| c > 0).collect();
                if m * g <= all.len() {
                    // The prefix, each once.
                    assert!(seen[..m * g].iter().all(|&c| c == 1), "g {g} m {m}");
                    assert_eq!(looked.len(), m * g);
                } else {
                    assert!(seen.iter().all(|&c| c == m * g / all.len()), "g {g} m {m}");
                }
            }
        }
        assert!(draw_candidates(&[], 4, 3).is_empty());
    }

    /// A coarse light [`behind`] a point gives it nothing: every VPL it stands for (every
    /// input light with a trilinear weight, eqs. 1, 2) is hidden by the surface there
    /// ([`super::facing`]), at every point the camera sees in the room and every coarse light its
    /// query at α = 4 returns. And the test bites: some lights are left out.
    #[test]
    fn lights_behind_a_point_give_it_nothing() {
        let f = Fixture::new();
        let backend = LghBackend::new(&f.lgh, 4.0).unwrap();
        let (mut left_out, mut kept) = (0, 0);
        for (point, normal) in f.seen(16, 12) {
            f.lgh
                .query(point.position, backend.blending(), |s| {
                    if s.level == 0 {
                        return;
                    }
                    let to = s.position - point.position;
                    if !behind(&point, normal, to, f.lgh.h(s.level)) {
                        kept += 1;
                        return;
                    }
                    left_out += 1;
                    crate::representatives::contributors(&f.lgh, s.level, s.index, |j, _, _| {
                        let q = f.vpls[j].position;
                        assert!(!super::super::facing(&point, normal, q), "{s:?}: VPL {j}");
                    });
                })
                .unwrap();
        }
        println!("{left_out} coarse lights left out, {kept} kept");
        assert!(left_out > 0 && kept > 0, "{left_out} {kept}");
    }

    /// The adaptive allocation (here 16 nested representatives, each drawn on its own, 2 per
    /// coarse light on average, shared per point by an unshadowed estimate, systematic Russian roulette
    /// below one) against brute force in the room: measured (32×24) 4.4% at α = 4 (the paper's
    /// Gaussian samples 54.6%) and 0.26% at α = 16. Asserted: it beats the Gaussian samples at α = 4 and
    /// is within issue 14's 1% at α = 16. (The issue's 3% at α = 4 is for 365K VPLs, where the
    /// default measures 2.3% on the Cornell box and 2.7–3.0% on Sponza, `docs/gi.md`; the room's 4,000 VPLs make
    /// coarse lights of a few VPLs each, where the roulette's noise weighs more.) And it is the
    /// same at any thread count: the roulette's numbers come from the shading point's own
    /// sequence.
    #[test]
    fn adaptive_representatives_meet_the_targets_at_any_thread_count() {
        let f = Fixture::new();
        let reps = Representatives::build_with(&f.lgh, Allocation::Nested(16));
        let (shader, camera) = (f.shader(), Fixture::camera(32, 24));
        let exact = f.exact(&shader, &camera);
        let render = |alpha: f32| {
            let backend = LghBackend::new(&f.lgh, alpha).unwrap();
            let coarse = Coarse::Adaptive {
                reps: &reps,
                mean: 2.0,
                blend: BlendAt::Centre,
                candidates: 1,
            };
            render_lgh(&f.scene, &camera, &backend, coarse, &shader, |_| {}).unwrap()
        };
        let at4 = rel_rmse(&render(4.0), &exact);
        let gaussian = rel_rmse(&f.isotropic(&shader, &camera, 4.0), &exact);
        let at16 = rel_rmse(&render(16.0), &exact);
        println!("adaptive: alpha 4 {at4:.4} (gaussian {gaussian:.4}), alpha 16 {at16:.4}");
        assert!(at4 < gaussian, "{at4} against {gaussian}");
        assert!(at16 <= 0.01, "{at16}");
        // Unbiased: the image's mean matches that of every coarse light shaded through all 16
        // of its representatives (the roulette's weights and the prefixes change the noise, not
        // the mean).
        let backend = LghBackend::new(&f.lgh, 4.0).unwrap();
        let all = Coarse::Representatives(&reps);
        let full = render_lgh(&f.scene, &camera, &backend, all, &shader, |_| {}).unwrap();
        let ratio = light_sum(&render(4.0)) / light_sum(&full);
        println!("adaptive mean over all-16 mean: {ratio:.5}");
        // Measured 1.00267, 0.27% off; bound 0.7% (2.6× it). The per-pixel noise is about the
        // 4.4% RMSE above, 0.16% over 768 pixels were they independent, more as neighbours
        // share lights: what is measured is that noise, and a bias of 1% fails.
        assert!((ratio - 1.0).abs() < 0.007, "{ratio}");
        assert_eq!(
            pool(1).install(|| render(4.0)),
            pool(3).install(|| render(4.0))
        );
    }

    /// The per-point refinement ([`refine`](super::super::refine)) against brute force in the
    /// room at α = 4 (1.25 representatives per coarse light on average, each drawn on its own,
    /// at most 32): the points whose estimated error may exceed the bound are shaded
    /// again, so fewer pixels err by more than it, the largest error falls and so does the
    /// image's; the refined points are counted; the image is the same on 1 and 3 threads.
    /// The bound is 3% here: at `lgh gi`'s 10% the room (48×36) has one pixel over to begin
    /// with, where Sponza had 1.2%. Measured (blended at the centres): 26.4% of the pixels
    /// over 3% without refinement, 6.9% with it (what is left is mostly the hierarchy's own
    /// smoothing, which the rule does not bound), the largest error 11.1% → 5.5%, the image's
    /// 3.68% → 2.70%, 918 of 955 points refined (at 3%, nearly every point's few samples may be off by that much); the
    /// mean 1.0027 times that of every representative. Asserted: the fraction over at least
    /// halves, the largest error and the image's fall, some points but not all are refined,
    /// the mean is within 0.7%.
    #[test]
    fn refined_points_err_less() {
        let f = Fixture::new();
        let reps = Representatives::build_with(&f.lgh, Allocation::Nested(32));
        let camera = Fixture::camera(48, 36);
        let exact = f.exact(&f.shader(), &camera);
        let backend = LghBackend::new(&f.lgh, 4.0).unwrap();
        let render = |point_error: Option<f32>| {
            let shader = Indirect::new(
                &f.scene,
                &f.vpls,
                super::super::IndirectSettings {
                    point_error,
                    ..f.shader().settings
                },
            );
            let coarse = Coarse::Adaptive {
                reps: &reps,
                mean: 1.25,
                blend: BlendAt::Centre,
                candidates: 1,
            };
            let r = render_lgh(&f.scene, &camera, &backend, coarse, &shader, |_| {}).unwrap();
            (r, shader.refined_points(), shader.bounded_points())
        };
        let (plain, none, _) = render(None);
        let (refined, count, bounded) = render(Some(0.03));
        let over = |r: &Rendered| lgh_image::point_errors(&r.image, &exact.image, 0.03).unwrap();
        let (before, after) = (over(&plain), over(&refined));
        let (e0, e1) = (rel_rmse(&plain, &exact), rel_rmse(&refined, &exact));
        let points = refined.pixels_shaded;
        println!(
            "over 3%: {:.4} -> {:.4}; largest {:.4} -> {:.4}; rel. RMSE {e0:.4} -> {e1:.4}; \
             refined {count} of {points}",
            before.over, after.over, before.max, after.max
        );
        assert_eq!(none, 0);
        assert_eq!(bounded, count);
        assert!(count > 0 && count < points, "{count} of {points}");
        assert!(
            after.over <= 0.5 * before.over,
            "{after:?} against {before:?}"
        );
        assert!(after.max < before.max, "{after:?} against {before:?}");
        assert!(e1 < e0, "{e1} against {e0}");
        // Stopping on the estimate itself barely biases it: the mean matches that of every
        // coarse light shaded through all its representatives. Measured 1.00274, 0.27% off;
        // bound 0.7% (2.55× it), as in
        // `adaptive_representatives_meet_the_targets_at_any_thread_count`.
        let shader = f.shader();
        let all = Coarse::Representatives(&reps);
        let full = render_lgh(&f.scene, &camera, &backend, all, &shader, |_| {}).unwrap();
        let ratio = light_sum(&refined) / light_sum(&full);
        println!("refined mean over all-32 mean: {ratio:.5}");
        assert!((ratio - 1.0).abs() < 0.007, "{ratio}");
        assert_eq!(
            pool(1).install(|| render(Some(0.03)).0),
            pool(3).install(|| render(Some(0.03)).0)
        );
    }
}
