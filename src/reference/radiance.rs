//! The light an encoder may read beyond the L2 SH of [`crate::encoders::encoder::FitInput`]:
//! SH of the radiance through band 4, the radiance in a direction (and the peer tool's fixed
//! Halton sample set of it), and the exact irradiance E/π at any normal. The peer's encodings
//! need these (SH L3/L4, spherical Gaussians and the H-basis fitted to radiance samples, the
//! ambient cube and dice fitted to irradiance).
//!
//! [`RadianceSource`] is the interface; [`MapLight`] is the map's (built by the runner, one per
//! case, for the light visible under the case's caps); [`ShLight`] is the fallback when only
//! L2 SH exist (probe sets, strips, claims that build inputs from SH): the light *is* then the
//! band-limited radiance Σ L_i Y_i.
//!
//! Everything is lazy and cached: an encoder that never asks pays nothing, and one that asks
//! twice (the timing pass refits) computes once. Every value is deterministic and does not depend
//! on the thread count (parallel work is reduced in a fixed order).

use crate::envmap::moments::RowMoments;
use crate::envmap::{EnvMap, LatLong};
use crate::math::cap::{Arcs, Cap};
use crate::math::colour::Rgb;
use crate::math::convention::direction;
use crate::math::halton::{peer_sphere_directions, PEER_SAMPLE_COUNT};
use crate::math::quadrature::{for_each_polar_node, gauss_legendre};
use crate::math::sh::Sh9;
use crate::math::sh4::{basis4, Sh25, N_SH4};
use crate::reference::exact::Reference;
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};
use std::sync::{Arc, Mutex, OnceLock};

/// One radiance sample: a unit direction and the radiance seen there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadianceSample {
    /// Unit world-space direction the radiance arrives from.
    pub direction: DVec3,
    /// Radiance seen along `direction`.
    pub radiance: Rgb,
}

/// The visible light of one fit, as encoders that need more than L2 SH read it. All values are
/// of the light the fit's `visible_sh` describes (the map under the case's caps; the whole map
/// with no effect). Directions and normals are world-space unit vectors (+Y up).
pub trait RadianceSource: Send + Sync + std::fmt::Debug {
    /// SH of the visible radiance through band 4 (index l² + l + m, FORMULAS §2 extended,
    /// [`crate::math::sh4`]); radiance, not E/π (apply [`Sh25::convolve_cosine`]). Bands 0–2
    /// agree with the input's `visible_sh` to rounding.
    fn sh4(&self) -> &Sh25;
    /// The visible radiance in direction `d`: for a map, the texel whose cell contains `d`
    /// (the nearest texel, as the peer reads it), zero where a cap hides `d`.
    fn radiance(&self, d: DVec3) -> Rgb;
    /// The peer tool's sample set: [`PEER_SAMPLE_COUNT`] Halton(2, 3) directions on the sphere
    /// ([`crate::math::halton`]), in the peer's order, with [`RadianceSource::radiance`] there.
    fn samples(&self) -> &[RadianceSample];
    /// The exact irradiance E/π at unit normal `n` of the visible light (no self-bounce: that
    /// is an encoder's business). For a map this is the case's exact reference.
    fn irradiance(&self, n: DVec3) -> Rgb;
    /// [`RadianceSource::irradiance`] at many normals, in their order.
    fn irradiance_many(&self, normals: &[DVec3]) -> Vec<Rgb> {
        normals.iter().map(|&n| self.irradiance(n)).collect()
    }
    /// E/π at the pixel centres of a `width`×`height` lat-long grid of normals (world
    /// orientation, row-major, [`LatLong::direction`]), cached per size: fitting targets that
    /// are the input, not part of the fit (its `fit_ns` excludes them, like the SH projection).
    fn irradiance_latlong(&self, width: usize, height: usize) -> Arc<Vec<Rgb>>;
    /// E/π at a fixed set of normals, such as a fit's quadrature rule (the H-basis's rule over
    /// the hemisphere about N), in their order. A map's light caches it by the set, compared
    /// bit for bit, so that it is input like [`RadianceSource::irradiance_latlong`] and not part
    /// of the fit's time; the default computes it on every call.
    fn irradiance_set(&self, normals: &[DVec3]) -> Arc<Vec<Rgb>> {
        Arc::new(self.irradiance_many(normals))
    }
}

/// A cache of irradiance targets by key: lat-long grids by size, normal sets by the normals.
struct Cache<K>(Mutex<Vec<(K, Arc<Vec<Rgb>>)>>);

impl<K> Default for Cache<K> {
    fn default() -> Self {
        Cache(Mutex::new(Vec::new()))
    }
}

impl<K: PartialEq> Cache<K> {
    fn get(&self, key: K, compute: impl FnOnce() -> Vec<Rgb>) -> Arc<Vec<Rgb>> {
        // The lock fails only if a thread panicked holding it; nothing here panics under it.
        if let Some((_, v)) = self.0.lock().expect("target cache").iter().find(|(k, _)| *k == key) {
            return v.clone();
        }
        // Computed outside the lock (it may run in parallel); a racing duplicate is identical.
        let v = Arc::new(compute());
        let mut g = self.0.lock().expect("target cache");
        if let Some((_, old)) = g.iter().find(|(k, _)| *k == key) {
            return old.clone();
        }
        g.push((key, v.clone()));
        v
    }
}

/// Lat-long grids by (width, height).
type GridCache = Cache<(usize, usize)>;

/// Normal sets, keyed by their normals' bits (so −0 and 0 differ, and no NaN ever matches).
#[derive(PartialEq)]
struct NormalsKey(Vec<[u64; 3]>);

impl NormalsKey {
    fn of(normals: &[DVec3]) -> Self {
        NormalsKey(normals.iter().map(|n| [n.x.to_bits(), n.y.to_bits(), n.z.to_bits()]).collect())
    }
}

/// The normals of a lat-long grid's pixel centres, row-major.
pub fn latlong_normals(width: usize, height: usize) -> Vec<DVec3> {
    let g = LatLong::new(width, height);
    (0..height).flat_map(|j| (0..width).map(move |i| (i, j))).map(|(i, j)| g.direction(i, j)).collect()
}

/// A map's visible light under a set of caps (none: the whole map).
pub struct MapLight<'a> {
    map: &'a EnvMap,
    moments: &'a RowMoments<'a>,
    masks: Vec<Cap>,
    polar_nodes: usize,
    sh4: OnceLock<Sh25>,
    samples: OnceLock<Vec<RadianceSample>>,
    reference: OnceLock<Reference<'a>>,
    grids: GridCache,
    sets: Cache<NormalsKey>,
}

impl std::fmt::Debug for MapLight<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "MapLight({}, {} caps)", self.map.name, self.masks.len())
    }
}

impl<'a> MapLight<'a> {
    /// The light of `map` inside every cap of `masks`; `moments` are the map's row moments and
    /// `polar_nodes` the exact reference's accuracy knob (its irradiance equals the case's
    /// [`Reference`] built from the same arguments, bit for bit). Nothing is computed yet.
    pub fn new(map: &'a EnvMap, moments: &'a RowMoments<'a>, masks: Vec<Cap>, polar_nodes: usize) -> Self {
        MapLight {
            map,
            moments,
            masks,
            polar_nodes,
            sh4: OnceLock::new(),
            samples: OnceLock::new(),
            reference: OnceLock::new(),
            grids: GridCache::default(),
            sets: Cache::default(),
        }
    }

    fn reference(&self) -> &Reference<'a> {
        self.reference.get_or_init(|| Reference::new(self.moments, self.masks.clone(), self.polar_nodes))
    }
}

impl RadianceSource for MapLight<'_> {
    fn sh4(&self) -> &Sh25 {
        self.sh4.get_or_init(|| project_sh4(self.map, &self.masks))
    }

    fn radiance(&self, d: DVec3) -> Rgb {
        if !self.masks.iter().all(|c| c.contains(d)) {
            return Rgb::ZERO;
        }
        let (i, j) = self.map.grid().texel_at(d);
        let t = self.map.texel(i, j);
        Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64)
    }

    fn samples(&self) -> &[RadianceSample] {
        self.samples.get_or_init(|| {
            peer_sphere_directions(PEER_SAMPLE_COUNT)
                .into_iter()
                .map(|d| RadianceSample { direction: d, radiance: self.radiance(d) })
                .collect()
        })
    }

    fn irradiance(&self, n: DVec3) -> Rgb {
        self.reference().irradiance(n)
    }

    fn irradiance_many(&self, normals: &[DVec3]) -> Vec<Rgb> {
        self.reference().irradiance_many(normals)
    }

    fn irradiance_latlong(&self, width: usize, height: usize) -> Arc<Vec<Rgb>> {
        self.grids.get((width, height), || self.reference().irradiance_latlong(LatLong::new(width, height)))
    }

    fn irradiance_set(&self, normals: &[DVec3]) -> Arc<Vec<Rgb>> {
        self.sets.get(NormalsKey::of(normals), || self.reference().irradiance_many(normals))
    }
}

/// The light of L2 SH alone: radiance Σ L_i Y_i(d) (band-limited, so it may dip below zero),
/// SH through band 4 with bands 3–4 zero, E/π from the cosine convolution (FORMULAS §3).
#[derive(Debug)]
pub struct ShLight {
    sh4: Sh25,
    irradiance: Sh9,
    samples: OnceLock<Vec<RadianceSample>>,
    grids: GridCacheDebug,
}

/// [`GridCache`] with a Debug that prints nothing.
#[derive(Default)]
struct GridCacheDebug(GridCache);

impl std::fmt::Debug for GridCacheDebug {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("..")
    }
}

impl ShLight {
    /// The light whose radiance SH are `sh`.
    pub fn new(sh: &Sh9) -> Self {
        ShLight {
            sh4: Sh25::from_sh9(sh),
            irradiance: sh.convolve_cosine(),
            samples: OnceLock::new(),
            grids: GridCacheDebug::default(),
        }
    }
}

impl RadianceSource for ShLight {
    fn sh4(&self) -> &Sh25 {
        &self.sh4
    }

    fn radiance(&self, d: DVec3) -> Rgb {
        self.sh4.eval(d, 2)
    }

    fn samples(&self) -> &[RadianceSample] {
        self.samples.get_or_init(|| {
            peer_sphere_directions(PEER_SAMPLE_COUNT)
                .into_iter()
                .map(|d| RadianceSample { direction: d, radiance: self.radiance(d) })
                .collect()
        })
    }

    fn irradiance(&self, n: DVec3) -> Rgb {
        self.irradiance.eval(n)
    }

    fn irradiance_latlong(&self, width: usize, height: usize) -> Arc<Vec<Rgb>> {
        self.grids.0.get((width, height), || self.irradiance_many(&latlong_normals(width, height)))
    }
}

/// Gauss–Legendre nodes per polar piece of [`project_sh4`].
const SH4_NODES: usize = 8;
/// Azimuth samples per parallel that resolve a band-4 basis function's Fourier series (degree
/// ≤ 4 in the map's azimuth θ, so any count above 8 is exact).
const SH4_AZIMUTH_SAMPLES: usize = 16;

/// SH through band 4 of the map's radiance inside every cap of `masks`: c_i = ∫ L·Y_i dω with
/// L piecewise constant over the texel cells.
///
/// Azimuth: on a parallel, each basis function is a trigonometric polynomial of degree ≤ 4 in
/// θ; its Fourier coefficients come exactly from 16 equally spaced samples, and the texels'
/// ∫ cos mθ, ∫ sin mθ over their (visible part of the) cell are closed forms. Polar: the
/// integrand is smooth in φ between cap breakpoints (a trigonometric polynomial of degree ≤ 6
/// without caps); 8 Gauss–Legendre nodes per piece, rows split at the caps' breakpoints and
/// into pieces no taller than π/128, as the reference's (`math::quadrature::for_each_polar_node`). Without caps this agrees with the exact
/// L2 projection ([`crate::reference::projection::project`]) to ~1e-15 relative (tested).
pub fn project_sh4(map: &EnvMap, masks: &[Cap]) -> Sh25 {
    let grid = map.grid();
    let rule = gauss_legendre(SH4_NODES);
    let breaks: Vec<f64> = masks.iter().flat_map(|c| c.breakpoints()).collect();
    let rows: Vec<Sh25> = (0..grid.height)
        .into_par_iter()
        .map(|j| {
            let row: Vec<Rgb> = map.row(j).iter().map(|t| Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64)).collect();
            let full = if masks.is_empty() { Some(arc_moments(&row, &grid, -PI, TAU)) } else { None };
            let (p0, p1) = (grid.phi_edge(j), grid.phi_edge(j + 1));
            let mut out = Sh25::ZERO;
            for_each_polar_node(p0, p1, &breaks, &rule, |phi, w| {
                let weight = w * phi.sin();
                let moments = match &full {
                    Some(m) => *m,
                    None => {
                        let (s, c) = phi.sin_cos();
                        let arcs = masks.iter().fold(Arcs::full(), |acc, m| acc.intersect(m.arc(s, c)));
                        let mut m = [[Rgb::ZERO; 2]; 5];
                        for arc in arcs.as_slice() {
                            let am = arc_moments(&row, &grid, arc.lo, arc.len);
                            for (x, y) in m.iter_mut().zip(am) {
                                x[0] += y[0];
                                x[1] += y[1];
                            }
                        }
                        m
                    }
                };
                add_parallel(&mut out, phi, weight, &moments);
            });
            out
        })
        .collect();
    rows.into_iter().fold(Sh25::ZERO, |mut a, b| {
        for (x, y) in a.0.iter_mut().zip(b.0) {
            *x += y;
        }
        a
    })
}

/// Adds `weight`·∫ L(θ) Y_i(θ, φ) dθ over one parallel, from the radiance's azimuth moments
/// (∫ L cos mθ, ∫ L sin mθ) and the basis functions' Fourier coefficients on that parallel.
fn add_parallel(out: &mut Sh25, phi: f64, weight: f64, moments: &[[Rgb; 2]; 5]) {
    let n = SH4_AZIMUTH_SAMPLES;
    let mut fc = [[[0.0f64; 2]; 5]; N_SH4];
    for s in 0..n {
        let theta = TAU * s as f64 / n as f64;
        let y = basis4(direction(theta, phi));
        for m in 0..5 {
            let (sm, cm) = (m as f64 * theta).sin_cos();
            let scale = if m == 0 { 1.0 / n as f64 } else { 2.0 / n as f64 };
            for (f, yi) in fc.iter_mut().zip(y) {
                f[m][0] += scale * yi * cm;
                f[m][1] += scale * yi * sm;
            }
        }
    }
    for (o, f) in out.0.iter_mut().zip(&fc) {
        let mut acc = Rgb::ZERO;
        for (mm, fm) in moments.iter().zip(f) {
            acc += mm[0] * fm[0] + mm[1] * fm[1];
        }
        *o += acc * weight;
    }
}

/// (∫ L cos mθ dθ, ∫ L sin mθ dθ) for m = 0..4 over the arc [lo, lo + len] of one row, L the
/// row's texels (piecewise constant in θ). Exact: per texel overlap [a, b],
/// ∫ cos mθ = 2 sin(m(b − a)/2) cos(m(a + b)/2)/m and ∫ sin mθ = 2 sin(m(b − a)/2) sin(m(a + b)/2)/m.
fn arc_moments(row: &[Rgb], grid: &LatLong, lo: f64, len: f64) -> [[Rgb; 2]; 5] {
    let mut out = [[Rgb::ZERO; 2]; 5];
    let w = row.len();
    let dt = grid.dtheta();
    let s0 = (lo + PI) / dt;
    let s1 = s0 + len.min(TAU) / dt;
    let mut k = s0.floor();
    while k < s1 {
        let (a, b) = (s0.max(k), s1.min(k + 1.0));
        if b > a {
            let l = row[(k as i64).rem_euclid(w as i64) as usize];
            let (ta, tb) = (-PI + a * dt, -PI + b * dt);
            let (half, mid) = (0.5 * (tb - ta), 0.5 * (ta + tb));
            out[0][0] += l * (tb - ta);
            for (m, o) in out.iter_mut().enumerate().skip(1) {
                let mf = m as f64;
                let amp = 2.0 * (mf * half).sin() / mf;
                let (sm, cm) = (mf * mid).sin_cos();
                o[0] += l * (amp * cm);
                o[1] += l * (amp * sm);
            }
        }
        k += 1.0;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::sh::N_SH;
    use crate::reference::projection::{project, project_visible};

    fn test_map() -> EnvMap {
        EnvMap::from_fn("t", 32, 16, |i, j| {
            let v = ((i * 7 + j * 3) % 11) as f32 * 0.5 + 0.1;
            [v, v * 0.5 + j as f32, (i as f32).sqrt()]
        })
        .unwrap()
    }

    /// Bands 0–2 equal the exact L2 projection (closed-form polar integrals) to rounding.
    #[test]
    fn bands_0_to_2_equal_the_exact_projection() {
        for map in [test_map(), EnvMap::from_fn("s", 4, 2, |i, j| [i as f32 + 1.0, j as f32, 0.5]).unwrap()] {
            let (a, b) = (project_sh4(&map, &[]), project(&map));
            let scale = b[0].abs().max_element();
            for i in 0..N_SH {
                assert!(
                    (a.0[i] - b[i]).abs().max_element() < 1e-13 * scale,
                    "{} c{i}: {} vs {}",
                    map.name,
                    a.0[i],
                    b[i]
                );
            }
        }
    }

    /// A polar cap of constant radiance about +Z on a fine map: its SH are zonal about z with the
    /// closed form c_l0 = 2π K_l0 ∫_{cos α}^1 P_l(z) dz, = 2π K_l0 (P_{l−1}(c) − P_{l+1}(c))/(2l+1)
    /// for l ≥ 1. The map's cells only approximate the cap's edge, so the match is to the
    /// resolution's order (the cell-average map of `scenes` is not used: it is L2-only).
    #[test]
    fn a_cap_light_has_its_closed_form_band_4() {
        let c = 0.5f64;
        let (w, h) = (512, 256);
        let g = LatLong::new(w, h);
        // Cell-average of the indicator by sub-sampling each cell 8×8.
        let map = EnvMap::from_fn("cap", w, h, |i, j| {
            let mut hit = 0;
            for a in 0..8 {
                for b in 0..8 {
                    let t = g.theta_edge(i) + (a as f64 + 0.5) / 8.0 * g.dtheta();
                    let p = g.phi_edge(j) + (b as f64 + 0.5) / 8.0 * PI / h as f64;
                    if direction(t, p).z > c {
                        hit += 1;
                    }
                }
            }
            [hit as f32 / 64.0; 3]
        })
        .unwrap();
        let sh = project_sh4(&map, &[]);
        let p = |l: usize, z: f64| match l {
            0 => 1.0,
            1 => z,
            2 => 0.5 * (3.0 * z * z - 1.0),
            3 => 0.5 * (5.0 * z * z * z - 3.0 * z),
            4 => (35.0 * z.powi(4) - 30.0 * z * z + 3.0) / 8.0,
            5 => (63.0 * z.powi(5) - 70.0 * z.powi(3) + 15.0 * z) / 8.0,
            _ => unreachable!(),
        };
        for l in 1..5usize {
            let k = ((2 * l + 1) as f64 / (4.0 * PI)).sqrt();
            let want = 2.0 * PI * k * (p(l - 1, c) - p(l + 1, c)) / (2 * l + 1) as f64;
            let got = sh.0[l * l + l].x;
            assert!((got - want).abs() < 2e-3 * want.abs().max(0.1), "l={l}: {got} vs {want}");
            for m in 1..=l {
                assert!(sh.0[l * l + l + m].x.abs() < 2e-3 && sh.0[l * l + l - m].x.abs() < 2e-3, "l={l} m={m}");
            }
        }
    }

    /// Under caps, bands 0–2 agree with the masked L2 projection run with the same polar rule
    /// (8 Gauss–Legendre nodes per piece between the caps' breakpoints) to rounding: the
    /// azimuth integrals are exact in both, by different routes (row moments there, texel walks
    /// and Fourier coefficients here).
    #[test]
    fn masked_bands_0_to_2_match_project_visible() {
        let map = test_map();
        let rm = RowMoments::new(&map);
        let n = DVec3::new(0.3, 0.5, 0.81).normalize();
        let caps = [Cap::hemisphere(n), Cap::new(DVec3::new(-0.2, 0.9, 0.1).normalize(), 0.5)];
        let a = project_sh4(&map, &caps);
        let b = project_visible(&rm, &caps, SH4_NODES);
        for i in 0..N_SH {
            assert!((a.0[i] - b[i]).abs().max_element() < 1e-12, "c{i}: {} vs {}", a.0[i], b[i]);
        }
    }

    /// The map light's radiance is the texel's, zero outside its caps; its samples are the
    /// peer's directions; its irradiance (one normal, a cached lat-long grid, a cached normal set)
    /// is the exact reference's, bit for bit; the SH light's irradiance is the cosine-convolved
    /// SH.
    #[test]
    fn map_and_sh_lights_agree_with_their_definitions() {
        let map = test_map();
        let rm = RowMoments::new(&map);
        let cap = Cap::hemisphere(DVec3::X);
        let light = MapLight::new(&map, &rm, vec![cap], 2);
        let d = map.grid().direction(20, 5);
        assert!(d.x > 0.0);
        let t = map.texel(20, 5);
        assert_eq!(light.radiance(d), Rgb::new(t[0] as f64, t[1] as f64, t[2] as f64));
        assert_eq!(light.radiance(map.grid().direction(3, 5)), Rgb::ZERO);
        assert_eq!(light.samples().len(), PEER_SAMPLE_COUNT);
        assert_eq!(light.samples()[7].direction, crate::math::halton::peer_sphere_direction(7));
        let r = Reference::new(&rm, vec![cap], 2);
        let n = DVec3::new(0.2, -0.3, 0.9).normalize();
        assert_eq!(light.irradiance(n), r.irradiance(n));
        let grid = light.irradiance_latlong(8, 4);
        assert_eq!(grid.len(), 32);
        assert_eq!(grid[9], r.irradiance(LatLong::new(8, 4).direction(1, 1)));
        assert!(Arc::ptr_eq(&grid, &light.irradiance_latlong(8, 4)));
        let set = [n, DVec3::X];
        let targets = light.irradiance_set(&set);
        assert_eq!(*targets, vec![r.irradiance(n), r.irradiance(DVec3::X)]);
        assert!(Arc::ptr_eq(&targets, &light.irradiance_set(&set)));
        assert!(!Arc::ptr_eq(&targets, &light.irradiance_set(&[DVec3::X, n])));

        let sh = project(&map);
        let sl = ShLight::new(&sh);
        assert_eq!(sl.irradiance(n), sh.convolve_cosine().eval(n));
        assert_eq!(sl.radiance(n), sh.eval(n));
        assert_eq!(sl.sh4().to_sh9(), sh);
    }
}
