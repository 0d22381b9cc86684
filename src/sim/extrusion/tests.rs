use super::*;
use proptest::prelude::*;
use rand::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

fn rng(seed: u64) -> Xoshiro256PlusPlus {
    Xoshiro256PlusPlus::seed_from_u64(seed)
}

/// Every invariant the model guarantees, checked against `params` from scratch.
fn check_invariants(ex: &Extruder, params: &ExtrusionParams) -> Result<(), String> {
    let n = params.n_monomers();
    let nb = ex.legs.len();
    if ex.captured.len() != nb || ex.load_sites.len() != nb || ex.bounds.len() != nb {
        return Err("parallel per-LEF vectors differ in length".into());
    }
    if nb + ex.n_unbound != params.n_lefs() {
        return Err(format!(
            "{nb} bound + {} unbound != {} LEFs",
            ex.n_unbound,
            params.n_lefs()
        ));
    }
    // No two legs on one site, and the occupancy array is exactly the set of legs.
    let mut occ = vec![false; n];
    for &(l, r) in &ex.legs {
        for s in [l, r] {
            if s >= n {
                return Err(format!("leg at {s} outside 0..{n}"));
            }
            if occ[s] {
                return Err(format!("two legs on site {s}"));
            }
            occ[s] = true;
        }
    }
    if occ != ex.occupied {
        return Err("occupancy array out of sync with the legs".into());
    }
    for (i, &(l, r)) in ex.legs.iter().enumerate() {
        if l >= r {
            return Err(format!("LEF {i}: l = {l} >= r = {r}"));
        }
        let chain = params
            .chains
            .iter()
            .find(|c| c.contains(&l))
            .ok_or("leg on no chain")?;
        if !chain.contains(&r) {
            return Err(format!("LEF {i}: legs {l}, {r} on different chains"));
        }
        if ex.bounds[i] != (chain.start, chain.end) {
            return Err(format!("LEF {i}: wrong chain bounds"));
        }
        let p = ex.load_sites[i];
        if !(chain.contains(&p) && chain.contains(&(p + 1)) && l <= p && p < r) {
            return Err(format!("LEF {i} ({l}, {r}): bad load site {p}"));
        }
        // A captured leg stands on an element that stops its direction.
        let [cl, cr] = ex.captured[i];
        let stop_at = |s: usize, left: bool| {
            params.elements.iter().any(|e| {
                e.position == s
                    && if left {
                        e.orientation.stops_left()
                    } else {
                        e.orientation.stops_right()
                    }
            })
        };
        if (cl && !stop_at(l, true)) || (cr && !stop_at(r, false)) {
            return Err(format!("LEF {i} captured off an element"));
        }
        // Permanent barriers: a leg that reaches one never leaves it. So a left leg loaded
        // at or right of a permanent left-stopping element never goes left of it, a right
        // leg loaded at or left of a permanent right-stopping one never goes right of it,
        // a leg on such an element is captured, and no loop strictly straddles a permanent
        // two-way barrier (a LEF loaded across b has b as one of its legs for ever).
        for e in params
            .elements
            .iter()
            .filter(|e| e.capture == 1.0 && e.release == 0.0)
        {
            let b = e.position;
            if e.orientation.stops_left() {
                if p >= b && l < b {
                    return Err(format!(
                        "LEF {i} loaded at {p} crossed + barrier {b}: l={l}"
                    ));
                }
                if l == b && !cl {
                    return Err(format!("left leg of LEF {i} on barrier {b} not captured"));
                }
            }
            if e.orientation.stops_right() {
                if p < b && r > b {
                    return Err(format!(
                        "LEF {i} loaded at {p} crossed - barrier {b}: r={r}"
                    ));
                }
                if r == b && !cr {
                    return Err(format!("right leg of LEF {i} on barrier {b} not captured"));
                }
            }
            if e.orientation == Orientation::Both && l < b && b < r {
                return Err(format!("LEF {i} ({l}, {r}) straddles two-way barrier {b}"));
            }
        }
    }
    // Loops are nested or disjoint (legs never cross): matching parentheses.
    let mut ends: Vec<(usize, usize, bool)> = Vec::with_capacity(2 * nb);
    for (i, &(l, r)) in ex.legs.iter().enumerate() {
        ends.push((l, i, true));
        ends.push((r, i, false));
    }
    ends.sort_unstable();
    let mut stack = Vec::new();
    for (_, i, is_left) in ends {
        if is_left {
            stack.push(i);
        } else if stack.pop() != Some(i) {
            return Err(format!("loop of LEF {i} crosses another loop"));
        }
    }
    Ok(())
}

/// A naive reference with the same rules and the same order of random draws, but no
/// bookkeeping: occupancy by scanning every leg, elements by scanning the element list,
/// chains by scanning the chain list.
struct Naive {
    p: ExtrusionParams,
    /// `(l, r, captured, load site)`.
    lefs: Vec<(usize, usize, [bool; 2], usize)>,
    unbound: usize,
}

impl Naive {
    fn new(p: &ExtrusionParams, rng: &mut Xoshiro256PlusPlus) -> Self {
        let mut me = Naive {
            p: p.clone(),
            lefs: Vec::new(),
            unbound: p.n_lefs(),
        };
        me.load(p.n_lefs(), rng);
        me
    }
    fn occupied(&self, s: usize) -> bool {
        self.lefs.iter().any(|&(l, r, _, _)| l == s || r == s)
    }
    fn chain(&self, s: usize) -> Range<usize> {
        self.p
            .chains
            .iter()
            .find(|c| c.contains(&s))
            .unwrap()
            .clone()
    }
    fn stop(&self, s: usize, left: bool) -> Option<(f64, f64)> {
        self.p
            .elements
            .iter()
            .find(|e| {
                e.position == s
                    && (if left {
                        e.orientation.stops_left()
                    } else {
                        e.orientation.stops_right()
                    })
            })
            .map(|e| (e.capture, e.release))
    }
    fn draw(rng: &mut Xoshiro256PlusPlus, q: f64) -> bool {
        if q == 1.0 {
            true
        } else if q == 0.0 {
            false
        } else {
            rng.r#gen::<f64>() < q
        }
    }
    fn site(&self, rng: &mut Xoshiro256PlusPlus) -> Option<usize> {
        let n = self.p.n_monomers();
        for _ in 0..LOAD_TRIES {
            let p = rng.gen_range(0..n - 1);
            if !self.occupied(p) && !self.occupied(p + 1) && self.chain(p).contains(&(p + 1)) {
                return Some(p);
            }
        }
        None
    }
    fn captures(&self, s: usize, left: bool, rng: &mut Xoshiro256PlusPlus) -> bool {
        match self.stop(s, left) {
            Some((c, _)) => Self::draw(rng, c),
            None => false,
        }
    }
    fn put(&self, p: usize, rng: &mut Xoshiro256PlusPlus) -> (usize, usize, [bool; 2], usize) {
        let cl = self.captures(p, true, rng);
        let cr = self.captures(p + 1, false, rng);
        (p, p + 1, [cl, cr], p)
    }
    fn load(&mut self, count: usize, rng: &mut Xoshiro256PlusPlus) {
        for _ in 0..count {
            if let Some(p) = self.site(rng) {
                // Occupy before the capture draws (they do not depend on occupancy).
                let lef = self.put(p, rng);
                self.lefs.push(lef);
                self.unbound -= 1;
            }
        }
    }
    fn step(&mut self, rng: &mut Xoshiro256PlusPlus) {
        let retry = self.unbound;
        let unload = 2.0 / self.p.processivity;
        let mut i = 0;
        while i < self.lefs.len() {
            if Self::draw(rng, unload) {
                let old = self.lefs[i];
                // Free the sites by moving the LEF off the polymer.
                self.lefs[i] = (usize::MAX, usize::MAX, [false; 2], 0);
                match self.site(rng) {
                    Some(p) => self.lefs[i] = self.put(p, rng),
                    None => {
                        let _ = old;
                        self.lefs.swap_remove(i);
                        self.unbound += 1;
                        continue;
                    }
                }
            } else {
                for left in [true, false] {
                    let (l, r, cap, _) = self.lefs[i];
                    let (s, k) = if left { (l, 0) } else { (r, 1) };
                    if cap[k] {
                        let (_, rel) = self.stop(s, left).unwrap();
                        if !Self::draw(rng, rel) {
                            continue;
                        }
                        self.lefs[i].2[k] = false;
                    }
                    let chain = self.chain(s);
                    let target = if left {
                        s.checked_sub(1).filter(|t| chain.contains(t))
                    } else {
                        Some(s + 1).filter(|t| chain.contains(t))
                    };
                    if let Some(t) = target {
                        if !self.occupied(t) {
                            if left {
                                self.lefs[i].0 = t;
                            } else {
                                self.lefs[i].1 = t;
                            }
                            self.lefs[i].2[k] = self.captures(t, left, rng);
                        }
                    }
                }
            }
            i += 1;
        }
        self.load(retry, rng);
    }
}

fn orientation() -> impl Strategy<Value = Orientation> {
    prop_oneof![
        Just(Orientation::Forward),
        Just(Orientation::Reverse),
        Just(Orientation::Both)
    ]
}

fn probability() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.0), Just(1.0), 0.0..=1.0]
}

/// Random valid parameters: 1-4 chains of 1-60 monomers, crowded (separation 2-4, some LEFs
/// then wait for room) to dilute, with elements (about a third permanent) deduplicated per
/// site and direction.
fn params() -> impl Strategy<Value = ExtrusionParams> {
    (
        prop::collection::vec(1usize..60, 1..5),
        2.0f64..300.0,
        prop_oneof![2.0f64..4.0, 1.0f64..40.0],
        prop::collection::vec(
            (
                0.0f64..1.0,
                orientation(),
                probability(),
                probability(),
                any::<bool>(),
            ),
            0..12,
        ),
    )
        .prop_filter_map("no room for the LEFs", |(lens, proc_, sep, els)| {
            let mut chains = Vec::new();
            let mut start = 0;
            for len in lens {
                chains.push(start..start + len);
                start += len;
            }
            let n = start;
            let mut elements: Vec<BoundaryElement> = Vec::new();
            for (x, orientation, capture, release, permanent) in els {
                let position = ((x * n as f64) as usize).min(n - 1);
                let e = if permanent {
                    BoundaryElement::permanent(position, orientation)
                } else {
                    BoundaryElement {
                        position,
                        orientation,
                        capture,
                        release,
                    }
                };
                let clash = elements.iter().any(|f| {
                    f.position == position
                        && ((f.orientation.stops_left() && orientation.stops_left())
                            || (f.orientation.stops_right() && orientation.stops_right()))
                });
                if !clash {
                    elements.push(e);
                }
            }
            let p = ExtrusionParams {
                chains,
                processivity: proc_,
                separation: sep,
                elements,
            };
            p.check().is_ok().then_some(p)
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Test 1: the invariants hold after loading and after every step.
    #[test]
    fn invariants_hold(p in params(), seed in any::<u64>(), steps in 0usize..300) {
        let mut r = rng(seed);
        let mut ex = Extruder::new(&p, &mut r).unwrap();
        if let Err(e) = check_invariants(&ex, &p) {
            return Err(TestCaseError::fail(format!("after loading: {e}")));
        }
        for t in 0..steps {
            ex.step(&mut r);
            if let Err(e) = check_invariants(&ex, &p) {
                return Err(TestCaseError::fail(format!("after step {}: {e}", t + 1)));
            }
        }
        prop_assert_eq!(ex.steps(), steps as u64);
    }

    /// The bookkept model follows the naive reference draw for draw.
    #[test]
    fn matches_naive_reference(p in params(), seed in any::<u64>(), steps in 0usize..150) {
        let mut r1 = rng(seed);
        let mut r2 = rng(seed);
        let mut ex = Extruder::new(&p, &mut r1).unwrap();
        let mut naive = Naive::new(&p, &mut r2);
        for t in 0..=steps {
            let fast: Vec<_> = ex
                .legs()
                .iter()
                .zip(ex.captured())
                .zip(ex.load_sites())
                .map(|((&(l, r), &c), &s)| (l, r, c, s))
                .collect();
            prop_assert_eq!(&fast, &naive.lefs, "step {}", t);
            prop_assert_eq!(ex.n_unbound(), naive.unbound);
            ex.step(&mut r1);
            naive.step(&mut r2);
        }
    }
}

/// Test 2: without elements, in the dilute limit, the mean loop size is λ - 1 (≈ λ).
///
/// After a step a LEF's age `k` (moves since loading) has probability `q (1 - q)^k`,
/// `q = 2 / λ`, and its loop is `2k + 1`: the mean is `2 (1 - q) / q + 1 = λ - 1`. 100 LEFs
/// 20,000 monomers apart (collisions lower the mean by about 0.25% here, 1% at 5,000 apart,
/// 4.5% at 1,000), for `400 λ` steps: the statistical error is about 0.5%.
#[test]
fn mean_loop_size_dilute() {
    for (lambda, seed) in [(100.0, 1), (30.0, 2)] {
        let p = ExtrusionParams::single_chain(2_000_000, lambda, 20_000.0);
        let mut r = rng(seed);
        let mut ex = Extruder::new(&p, &mut r).unwrap();
        assert_eq!(ex.n_lefs(), 100);
        for _ in 0..(10.0 * lambda) as usize {
            ex.step(&mut r);
        }
        let (mut sum, mut count) = (0.0, 0usize);
        for _ in 0..(400.0 * lambda) as usize {
            ex.step(&mut r);
            // Room everywhere: an unloaded LEF reloads in the same step.
            assert_eq!(ex.legs().len(), 100);
            sum += ex.legs().iter().map(|&(l, r)| (r - l) as f64).sum::<f64>();
            count += ex.legs().len();
        }
        let mean = sum / count as f64;
        let expected = lambda - 1.0;
        eprintln!("λ = {lambda}: mean loop size {mean:.2}, closed form λ - 1 = {expected}");
        assert!(
            (mean - expected).abs() < 0.02 * expected,
            "λ = {lambda}: mean loop size {mean} vs {expected}"
        );
    }
}

/// `replicas` runs of a chain of 600 monomers with one LEF and permanent elements at
/// `a = 50` (`orientation_a`) and `b = 550` (the opposite orientation). Returns the
/// fraction of steps with the loop exactly `(a, b)`, the fraction of steps of LEFs loaded
/// inside (`a <= p < b`) with `l < a < b < r`, and whether a LEF loaded inside ever had a
/// leg outside `[a, b]`.
fn domain_stats(orientation_a: Orientation, processivity: f64) -> (f64, f64, bool) {
    let (a, b, replicas, burn_in, steps) = (50, 550, 60, 2_000, 30_000);
    let orientation_b = match orientation_a {
        Orientation::Forward => Orientation::Reverse,
        _ => Orientation::Forward,
    };
    let p = ExtrusionParams {
        elements: vec![
            BoundaryElement::permanent(a, orientation_a),
            BoundaryElement::permanent(b, orientation_b),
        ],
        ..ExtrusionParams::single_chain(600, processivity, 600.0)
    };
    let (mut exact, mut inside, mut spanning, mut escaped) = (0usize, 0usize, 0usize, false);
    for seed in 0..replicas {
        let mut r = rng(100 + seed);
        let mut ex = Extruder::new(&p, &mut r).unwrap();
        assert_eq!(ex.n_lefs(), 1);
        for t in 0..burn_in + steps {
            ex.step(&mut r);
            let (l, r) = ex.legs()[0];
            let s = ex.load_sites()[0];
            if a <= s && s < b {
                escaped |= l < a || r > b;
                if t >= burn_in {
                    inside += 1;
                    spanning += (l < a && r > b) as usize;
                }
            }
            if t >= burn_in {
                exact += ((l, r) == (a, b)) as usize;
            }
        }
    }
    let total = (replicas as usize * steps) as f64;
    (
        exact as f64 / total,
        spanning as f64 / inside as f64,
        escaped,
    )
}

/// Test 3: convergent permanent barriers (+ at a, - at b) hold a loop loaded between them in
/// [a, b] and anchor it at exactly (a, b); swapped (- at a, + at b) they let it through.
///
/// Closed forms for one unobstructed LEF on a chain of `n` sites: after a step its age `k`
/// (moves since loading) has probability `q (1 - q)^k`, `q = 2 / λ`, and a LEF loaded at
/// `p` (uniform over the `n - 1` positions) in `a <= p < b` reaches `(a, b)` once
/// `k >= m(p) = max(p - a, b - 1 - p)`; LEFs loaded outside never do (they are caught by
/// one element only). So the fraction of steps at `(a, b)` is
/// `sum_{p=a}^{b-1} (1 - q)^m(p) / (n - 1)`. Swapped, a LEF loaded inside spans `[a, b]`
/// once `k >= m(p) + 1`: a fraction `sum_{p=a}^{b-1} (1 - q)^(m(p) + 1) / (b - a)` of the
/// steps of LEFs loaded inside.
#[test]
fn convergent_rule() {
    let (n, a, b, lambda) = (600usize, 50usize, 550usize, 1000.0);
    let q: f64 = 2.0 / lambda;
    let m = |p: usize| (p - a).max(b - 1 - p) as i32;
    let exact_expected = (a..b).map(|p| (1.0 - q).powi(m(p))).sum::<f64>() / (n - 1) as f64;
    let span_expected = (a..b).map(|p| (1.0 - q).powi(m(p) + 1)).sum::<f64>() / (b - a) as f64;

    let (exact, spanning, escaped) = domain_stats(Orientation::Forward, lambda);
    eprintln!(
        "convergent: loop (a, b) {exact:.4} of the steps (closed form {exact_expected:.4}), \
         spanning {spanning}"
    );
    assert!(!escaped, "a loop loaded in [a, b] left it");
    assert_eq!(spanning, 0.0, "a loop spanned a convergent domain");
    assert!(
        (exact - exact_expected).abs() < 0.03,
        "loop (a, b) {exact} of the time, expected {exact_expected}"
    );

    let (exact, spanning, escaped) = domain_stats(Orientation::Reverse, lambda);
    eprintln!(
        "divergent: loop (a, b) {exact:.4} of the steps, spanning {spanning:.4} \
         (closed form {span_expected:.4})"
    );
    assert!(
        escaped,
        "no loop loaded in [a, b] passed the swapped elements"
    );
    // The legs pass a and b at the same step only if a + b is odd: never here.
    assert_eq!(exact, 0.0, "loop (a, b) with divergent sites");
    assert!(
        (spanning - span_expected).abs() < 0.03,
        "loops spanned [a, b] {spanning} of the time, expected {span_expected}"
    );
}

/// A leg watched by [`capture_and_release`].
struct Watched {
    lef: usize,
    /// 0 for the left leg, 1 for the right one.
    leg: usize,
    /// The element's site.
    site: usize,
    /// The step it arrived on the site and whether it was captured then.
    arrival: Option<(u64, bool)>,
}

/// Test 4: a leg arriving on an element is captured with probability `capture` (once per
/// arrival), and a captured leg stays on the site `1 / release` steps on average (from the
/// step it arrives to the step it moves on).
///
/// Chains of 20 monomers with a two-way element at site 10 of each; LEFs practically never
/// unload, so the LEFs of a chain stay there. Only chains holding exactly one LEF are
/// measured: its leg facing the element (the left leg if loaded at `p >= 10`, else the right
/// one) arrives there once, nothing blocks it, and no stay is cut short by unloading.
#[test]
fn capture_and_release() {
    for (capture, release, seed) in [(0.6, 0.05, 4), (1.0, 0.5, 5)] {
        let (n_chains, len, site) = (8000, 20, 10);
        let p = ExtrusionParams {
            chains: (0..n_chains).map(|c| c * len..(c + 1) * len).collect(),
            processivity: 1e15,
            separation: len as f64,
            elements: (0..n_chains)
                .map(|c| BoundaryElement {
                    position: c * len + site,
                    orientation: Orientation::Both,
                    capture,
                    release,
                })
                .collect(),
        };
        let mut r = rng(seed);
        let mut ex = Extruder::new(&p, &mut r).unwrap();
        assert_eq!(ex.n_unbound(), 0);
        let mut per_chain = vec![0usize; n_chains];
        for &(l, _) in ex.legs() {
            per_chain[l / len] += 1;
        }
        let mut watched: Vec<Watched> = Vec::new();
        for (i, &s) in ex.load_sites().iter().enumerate() {
            let c = s / len;
            if per_chain[c] == 1 {
                let k = usize::from(s < c * len + site);
                watched.push(Watched {
                    lef: i,
                    leg: k,
                    site: c * len + site,
                    arrival: None,
                });
            }
        }
        let load_sites = ex.load_sites().to_vec();
        let (mut arrivals, mut captures, mut dwell) = (0usize, 0usize, Vec::new());
        let leg = |ex: &Extruder, i: usize, k: usize| {
            let (l, r) = ex.legs()[i];
            (if k == 0 { l } else { r }, ex.captured()[i][k])
        };
        let mut observe = |ex: &Extruder, t: u64, watched: &mut Vec<_>| {
            watched.retain_mut(|w: &mut Watched| {
                let (pos, cap) = leg(ex, w.lef, w.leg);
                match w.arrival {
                    None if pos == w.site => {
                        arrivals += 1;
                        captures += cap as usize;
                        w.arrival = Some((t, cap));
                        true
                    }
                    Some((t0, was_captured)) if pos != w.site => {
                        if was_captured {
                            dwell.push((t - t0) as f64);
                        } else {
                            assert_eq!(t - t0, 1, "an uncaptured leg was held");
                        }
                        false
                    }
                    _ => true,
                }
            });
        };
        observe(&ex, 0, &mut watched);
        let mut t = 0;
        while !watched.is_empty() && t < 100_000 {
            t += 1;
            ex.step(&mut r);
            observe(&ex, t, &mut watched);
        }
        assert!(watched.is_empty(), "a leg never left the element");
        assert_eq!(ex.load_sites(), &load_sites[..], "a LEF unloaded");
        let fraction = captures as f64 / arrivals as f64;
        let mean = dwell.iter().sum::<f64>() / dwell.len() as f64;
        eprintln!(
            "capture {capture}: {captures} of {arrivals} arrivals captured ({fraction:.4}); \
             release {release}: mean stay {mean:.3} steps (1/release = {})",
            1.0 / release
        );
        assert!(arrivals > 2500, "{arrivals} arrivals");
        assert!(
            (fraction - capture).abs() < 0.04,
            "captured {fraction} of arrivals, expected {capture}"
        );
        assert!(
            (mean * release - 1.0).abs() < 0.08,
            "release {release}: mean stay {mean}, expected {}",
            1.0 / release
        );
    }
}

/// Test 5: the same seed gives the same trajectory; another seed another one.
#[test]
fn deterministic() {
    let p = ExtrusionParams {
        elements: vec![
            BoundaryElement {
                position: 100,
                orientation: Orientation::Forward,
                capture: 0.7,
                release: 0.01,
            },
            BoundaryElement::permanent(300, Orientation::Both),
        ],
        ..ExtrusionParams {
            chains: vec![0..250, 250..500],
            processivity: 80.0,
            separation: 20.0,
            elements: Vec::new(),
        }
    };
    let run = |seed| {
        let mut r = rng(seed);
        let mut ex = Extruder::new(&p, &mut r).unwrap();
        for _ in 0..1000 {
            ex.step(&mut r);
        }
        (ex.legs().to_vec(), ex.captured().to_vec())
    };
    assert_eq!(run(7), run(7));
    assert_ne!(run(7).0, run(8).0);
}

/// Test 6: `check` rejects each bad parameter with a message naming it.
#[test]
fn check_messages() {
    let good = ExtrusionParams {
        elements: vec![BoundaryElement::permanent(5, Orientation::Forward)],
        ..ExtrusionParams {
            chains: vec![0..50, 50..100],
            processivity: 20.0,
            separation: 10.0,
            elements: Vec::new(),
        }
    };
    assert_eq!(good.check(), Ok(()));
    let expect = |p: ExtrusionParams, words: &[&str]| {
        let e = p.check().expect_err("accepted bad parameters");
        let msg = e.to_string();
        for w in words {
            assert!(msg.contains(w), "{msg:?} does not mention {w:?}");
        }
        assert!(Extruder::new(&p, &mut rng(0)).is_err());
    };
    let with = |f: &dyn Fn(&mut ExtrusionParams)| {
        let mut p = good.clone();
        f(&mut p);
        p
    };
    expect(with(&|p| p.chains.clear()), &["chains", "empty"]);
    expect(
        with(&|p| p.chains = vec![1..50, 50..100]),
        &["chains", "1..50", "start at 0"],
    );
    expect(
        with(&|p| p.chains = vec![0..50, 60..100]),
        &["chains", "chain 1", "start at 50"],
    );
    expect(
        with(&|p| p.chains = vec![0..50, 40..100]),
        &["chains", "start at 50"],
    );
    expect(
        with(&|p| p.chains = vec![0..50, 50..50]),
        &["chains", "chain 1", "empty"],
    );
    for bad in [0.0, -5.0, 1.5, f64::NAN, f64::INFINITY] {
        expect(with(&|p| p.processivity = bad), &["processivity"]);
    }
    for bad in [0.0, -1.0, 0.5, f64::NAN, f64::INFINITY] {
        expect(with(&|p| p.separation = bad), &["separation"]);
    }
    // 100 monomers, separation 1.5 -> 67 LEFs > 50.
    expect(
        with(&|p| p.separation = 1.5),
        &["separation", "67 LEFs", "at most 50"],
    );
    // Odd chains: 3 + 3 monomers hold 2 LEFs, not 3.
    expect(
        with(&|p| {
            p.chains = vec![0..3, 3..6];
            p.separation = 2.0;
            p.elements.clear();
        }),
        &["3 LEFs", "at most 2"],
    );
    expect(
        with(&|p| p.chains = std::iter::once(0..1).collect()),
        &["at most 0"],
    );
    expect(
        with(&|p| {
            p.elements
                .push(BoundaryElement::permanent(100, Orientation::Both))
        }),
        &["element 1", "position 100", "100 monomers"],
    );
    for bad in [-0.1, 1.1, f64::NAN] {
        expect(
            with(&|p| p.elements[0].capture = bad),
            &["element 0", "capture"],
        );
        expect(
            with(&|p| p.elements[0].release = bad),
            &["element 0", "release"],
        );
    }
    expect(
        with(&|p| {
            p.elements
                .push(BoundaryElement::permanent(5, Orientation::Both))
        }),
        &["elements 0 and 1", "position 5", "left"],
    );
    // A + and a - element may share a site.
    let mut p = good.clone();
    p.elements
        .push(BoundaryElement::permanent(5, Orientation::Reverse));
    assert_eq!(p.check(), Ok(()));
}

/// Loading is uniform over the free positions of all chains, and never across a chain end.
#[test]
fn loading_uniform() {
    // Chains 0..3 and 3..6: allowed p are 0, 1, 3, 4; one LEF each time.
    let p = ExtrusionParams {
        chains: vec![0..3, 3..6],
        processivity: 2.0,
        separation: 6.0,
        elements: Vec::new(),
    };
    let mut r = rng(9);
    let mut ex = Extruder::new(&p, &mut r).unwrap();
    let mut counts = [0usize; 6];
    let draws = 40_000;
    for _ in 0..draws {
        // processivity 2: unload and reload every step.
        ex.step(&mut r);
        counts[ex.load_sites()[0]] += 1;
    }
    assert_eq!((counts[2], counts[5]), (0, 0), "{counts:?}");
    for s in [0, 1, 3, 4] {
        let f = counts[s] as f64 / draws as f64;
        assert!((f - 0.25).abs() < 0.01, "{counts:?}");
    }
}
