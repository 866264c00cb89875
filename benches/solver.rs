//! Benchmarks of issue 11, item 7: the cost of one 60 Hz frame of KJOINT2 (4 substeps,
//! `Kn` = 1e12) against rapier 0.36 impulse joints on the same bodies (`dt` = 1/60 s,
//! 4 solver iterations), both in the same run, for the scenes of `benches/scenes.rs`:
//!
//! | criterion group | sizes (`cargo bench`) | reference |
//! |---|---|---|
//! | `chain` | 1000, 10 000 rods | revolute impulse joints |
//! | `pendulums` | 1000, 10 000 | revolute impulse joints |
//! | `resting` | 1000 pendulums hanging at rest, timed after 90 frames (asleep on both sides) | revolute impulse joints |
//! | `tree` | leaves first 511, 4095 joints; root first 255, 511 | revolute impulse joints, same order |
//! | `hub` | 300 rods (301 spherical joints) | spherical impulse joints |
//! | `contacts` | 50 groups of 3 capsules | the same bodies without joints, 4 × 1/240 s (and, for the record, rapier's own revolute joints at 1/60 s, and the bodies without joints taken through `get_mut` before each step as the joint set takes them: what rapier itself does for bodies written between steps); every side timed over the same second after landing (frames 60–120, rebuilt and settled untimed) |
//! | `urdf_arm` | `assets/urdf/arm.urdf` (3 joints) | `rapier3d-urdf` impulse joints |
//! | `four_bar` | the free loop (4 joints) | revolute impulse joints |
//! | `ring` | 48 rods hinged into a ring and pinned at a corner (one loop island of 49 joints) | revolute impulse joints |
//!
//! Bench ids are `group/side/size`, `side` = `kjoint2`, `rapier` (with `_root_first` /
//! `_leaves_first` for the trees), and for the contacts also `rapier_joints` and
//! `rapier_written`. After the groups, a table gives the ratio KJOINT2/rapier
//! of the mean frame times (criterion's mean point estimates, read from
//! `target/criterion/<group>/<side>/<size>/new/estimates.json`; criterion's own line shows
//! the slope instead when it sampled linearly, which differs by a few per cent) and the cost exponents
//! `log(t₂/t₁)/log(n₂/n₁)` of the chain, the pendulums and the trees; then the contact
//! ratio and the chain's, the pendulums' and the leaves-first tree's exponents measured
//! interleaved (both sides, or both sizes, built and timed one right after the other over
//! several rounds: ids `contacts/interleaved/50`, `exponents/interleaved/chain`,
//! `.../pendulums`, `.../tree`); then the peak resident
//! memory of the 10 000-link chain on either side, each built and stepped 3 frames in a
//! fresh process (this binary re-run with `RAPIER_KJOINT_PEAK_MEMORY=side:links:frames`,
//! as `examples/peak_memory.rs` does).
//!
//! A measurement that criterion would need more than a minute for (its 10 samples of at
//! least one frame, judged from one probe frame) is timed instead over at most 3 frames with
//! `Instant` and marked so (the root-first trees and the hub with the current solver).
//!
//! ```sh
//! cargo bench --bench solver                        # everything (≈ 3 min on 2 cores today)
//! cargo bench --bench solver -- chain               # one group (criterion's regex filter)
//! cargo bench --bench solver -- 'tree/kjoint2_leaves'
//! cargo bench --bench solver -- peak_memory         # the memory figures only
//! cargo bench --bench solver -- interleaved         # the interleaved measures only
//! cargo test --bench solver                         # test mode: tiny sizes, one frame each
//! ```
//!
//! Criterion settings: 10 samples, 1 s warm-up, 3 s measurement (override them on the
//! command line, e.g. `-- --measurement-time 10`). Each timed frame continues the same
//! simulation; the contact scene is first run for 1 s so that the capsules have landed.

#[path = "scenes.rs"]
mod scenes;

use criterion::{BenchmarkId, Criterion};
use regex::Regex;
use scenes::{MemorySide, Scene, TreeOrder};
use std::cell::Cell;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::rc::Rc;
use std::time::{Duration, Instant, SystemTime};

/// Longest a criterion measurement may take before the bench times a few frames itself.
const BUDGET: Duration = Duration::from_secs(60);
/// Frames timed with `Instant` when criterion would exceed [`BUDGET`].
const MAX_MANUAL_FRAMES: usize = 3;
/// Frames the resting pendulums run before they are timed (1.5 s: asleep on both sides).
const RESTING_SETTLE: usize = 90;
/// Criterion's sample count here (its minimum).
const SAMPLES: usize = 10;
/// Environment variable of the peak-memory child processes: `side:links:frames`.
const MEMORY_ENV: &str = "RAPIER_KJOINT_PEAK_MEMORY";

/// Scene sizes: the benchmark's, or tiny ones when criterion runs the bench as a test.
struct Sizes {
    chain: [usize; 2],
    pendulums: [usize; 2],
    /// resting pendulums (asleep once settled)
    resting: usize,
    /// depths (2^d − 1 joints)
    tree_leaves_first: [u32; 2],
    tree_root_first: [u32; 2],
    hub: usize,
    capsule_groups: usize,
    /// frames run before timing the contact scene (the capsules land)
    contact_settle: usize,
    memory_chain: usize,
    memory_frames: usize,
}

impl Sizes {
    fn new(bench: bool) -> Self {
        if bench {
            Sizes {
                chain: [1000, 10_000],
                pendulums: [1000, 10_000],
                resting: 1000,
                tree_leaves_first: [9, 12],
                tree_root_first: [8, 9],
                hub: 300,
                capsule_groups: 50,
                contact_settle: 60,
                memory_chain: 10_000,
                memory_frames: 3,
            }
        } else {
            Sizes {
                chain: [10, 100],
                pendulums: [10, 100],
                resting: 10,
                tree_leaves_first: [3, 5],
                tree_root_first: [3, 4],
                hub: 8,
                capsule_groups: 2,
                contact_settle: 0,
                memory_chain: 10,
                memory_frames: 1,
            }
        }
    }
}

/// What the command line says (criterion parses it too; this reads what the bench needs
/// before its slow set-ups: the mode and criterion's name filter).
struct Args {
    bench: bool,
    list: bool,
    filter: Filter,
    samples: usize,
}

enum Filter {
    All,
    Regex(Regex),
    Exact(String),
    Nothing,
}

impl Args {
    fn parse() -> Self {
        // criterion's options that take a value
        const VALUED: &[&str] = &[
            "-c",
            "--color",
            "--colour",
            "-s",
            "--save-baseline",
            "-b",
            "--baseline",
            "--baseline-lenient",
            "--format",
            "--profile-time",
            "--load-baseline",
            "--sample-size",
            "--warm-up-time",
            "--measurement-time",
            "--nresamples",
            "--noise-threshold",
            "--confidence-level",
            "--significance-level",
            "--plotting-backend",
            "--output-format",
        ];
        let (mut bench, mut test, mut list, mut exact, mut ignored) =
            (false, false, false, false, false);
        let mut samples = SAMPLES;
        let mut filter = None;
        let mut args = std::env::args().skip(1);
        while let Some(a) = args.next() {
            match a.as_str() {
                "--bench" => bench = true,
                "--test" => test = true,
                "--list" => list = true,
                "--exact" => exact = true,
                "--ignored" => ignored = true,
                "--sample-size" => {
                    if let Some(n) = args.next().and_then(|v| v.parse().ok()) {
                        samples = n;
                    }
                }
                _ if a.starts_with("--sample-size=") => {
                    samples = a["--sample-size=".len()..].parse().unwrap_or(samples)
                }
                _ if VALUED.contains(&a.as_str()) => {
                    args.next();
                }
                _ if a.starts_with('-') => {}
                _ => filter = filter.or(Some(a)),
            }
        }
        let filter = match filter {
            _ if ignored => Filter::Nothing,
            None => Filter::All,
            Some(f) if exact => Filter::Exact(f),
            // criterion exits on an invalid regex when it parses the arguments
            Some(f) => Regex::new(&f).map(Filter::Regex).unwrap_or(Filter::Nothing),
        };
        Args {
            bench: bench && !test,
            list,
            filter,
            samples,
        }
    }

    fn matches(&self, id: &str) -> bool {
        match &self.filter {
            Filter::All => true,
            Filter::Regex(r) => r.is_match(id),
            Filter::Exact(e) => e == id,
            Filter::Nothing => false,
        }
    }
}

/// Who is timed.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Side {
    Kjoint,
    Rapier,
    /// rapier's own joints where the reference has none (contacts)
    RapierJoints,
    /// the reference without joints, its bodies written before each step as the joint set
    /// writes them (contacts: [`scenes::Scene::rapier_unjointed_written`])
    RapierWritten,
}

impl Side {
    fn name(self) -> &'static str {
        match self {
            Side::Kjoint => "kjoint2",
            Side::Rapier => "rapier",
            Side::RapierJoints => "rapier_joints",
            Side::RapierWritten => "rapier_written",
        }
    }
}

/// One measured frame time.
#[derive(Clone, Copy, Debug)]
struct Timed {
    /// mean frame time \[s\]
    mean: f64,
    /// frames timed with `Instant` instead of criterion (0 = criterion)
    manual_frames: usize,
}

/// Result key: group, variant (tree order or ""), side, size.
type Key = (&'static str, &'static str, Side, usize);

/// A world to time: one call = one 60 Hz frame.
type Stepper = Box<dyn FnMut()>;

/// Frames of the contact scene timed from one settled start (1 s of simulated time, the
/// frames after the capsules have landed), on every side alike.
const CONTACT_WINDOW: usize = 60;

/// Rounds of the interleaved measure of the contact scene ([`contacts_interleaved`]).
const INTERLEAVED_ROUNDS: usize = 20;

/// One bench of a group.
struct Case {
    variant: &'static str,
    side: Side,
    size: usize,
    /// frames run before any timing
    settle: usize,
    /// Frames timed from one start before the world is rebuilt and settled again (untimed);
    /// 0: one world for every frame. A scene whose cost changes as it evolves (capsules
    /// piling up or rolling off their box) is timed over the same window of simulated time
    /// on both sides, whatever the number of frames criterion asks of each.
    window: usize,
    build: Box<dyn Fn() -> Stepper>,
}

/// Both sides of a scene.
fn pair(
    variant: &'static str,
    size: usize,
    settle: usize,
    scene: impl Fn() -> Scene + 'static,
) -> Vec<Case> {
    // built lazily (only the benches that pass the filter pay for it), once for both sides
    let scene = Rc::new(LazyScene::new(scene));
    vec![
        lazy_case(variant, Side::Kjoint, size, settle, 0, scene.clone()),
        lazy_case(variant, Side::Rapier, size, settle, 0, scene),
    ]
}

struct LazyScene {
    make: Box<dyn Fn() -> Scene>,
    scene: std::cell::OnceCell<Rc<Scene>>,
}

impl LazyScene {
    fn new(make: impl Fn() -> Scene + 'static) -> Self {
        LazyScene {
            make: Box::new(make),
            scene: std::cell::OnceCell::new(),
        }
    }
    fn get(&self) -> Rc<Scene> {
        self.scene.get_or_init(|| Rc::new((self.make)())).clone()
    }
}

fn lazy_case(
    variant: &'static str,
    side: Side,
    size: usize,
    settle: usize,
    window: usize,
    scene: Rc<LazyScene>,
) -> Case {
    Case {
        variant,
        side,
        size,
        settle,
        window,
        build: Box::new(move || -> Stepper {
            let scene = scene.get();
            match side {
                Side::Kjoint => {
                    let mut w = scene.kjoint();
                    Box::new(move || w.frame())
                }
                Side::Rapier => {
                    let mut w = scene.rapier();
                    Box::new(move || w.frame())
                }
                Side::RapierJoints => {
                    let mut w = scene.rapier_joints();
                    Box::new(move || w.frame())
                }
                Side::RapierWritten => {
                    let mut w = scene.rapier_unjointed_written();
                    Box::new(move || w.frame())
                }
            }
        }),
    }
}

struct Runner {
    args: Args,
    results: BTreeMap<Key, Timed>,
    /// (group, variant, size) in the order they ran
    order: Vec<(&'static str, &'static str, usize)>,
    /// criterion's output directory
    criterion_dir: PathBuf,
    started: SystemTime,
}

impl Runner {
    fn new(args: Args) -> Self {
        // where criterion writes: $CRITERION_HOME, else <target dir>/criterion (this binary
        // is <target dir>/<profile>/deps/solver-…)
        let criterion_dir = std::env::var_os("CRITERION_HOME")
            .map(PathBuf::from)
            .or_else(|| {
                let exe = std::env::current_exe().ok()?;
                Some(exe.parent()?.parent()?.parent()?.join("criterion"))
            })
            .unwrap_or_else(|| PathBuf::from("target/criterion"));
        Runner {
            args,
            results: BTreeMap::new(),
            order: Vec::new(),
            criterion_dir,
            started: SystemTime::now(),
        }
    }

    /// Criterion's mean point estimate \[s\] of a bench that ran in this process.
    fn criterion_mean(&self, group: &str, function: &str, size: usize) -> Option<f64> {
        let path = self
            .criterion_dir
            .join(group)
            .join(function)
            .join(size.to_string())
            .join("new/estimates.json");
        let modified = std::fs::metadata(&path).ok()?.modified().ok()?;
        if modified < self.started {
            return None; // from an earlier run
        }
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()?;
        Some(v["mean"]["point_estimate"].as_f64()? * 1e-9)
    }

    /// Runs the criterion group `group` over `cases`.
    fn group(&mut self, c: &mut Criterion, group: &'static str, cases: Vec<Case>) {
        let mut g = c.benchmark_group(group);
        for case in cases {
            let function = if case.variant.is_empty() {
                case.side.name().to_string()
            } else {
                format!("{}_{}", case.side.name(), case.variant)
            };
            let id = BenchmarkId::new(&function, case.size);
            if !self
                .args
                .matches(&format!("{group}/{function}/{}", case.size))
            {
                continue;
            }
            if self.args.list {
                g.bench_function(id, |b| b.iter(|| ()));
                continue;
            }
            let key = (group, case.variant, case.side, case.size);
            let mut frame = (case.build)();
            for _ in 0..case.settle {
                frame();
            }
            let mut in_window = 0usize;
            if self.args.bench {
                // one probe frame: would criterion's samples (≥ 1 frame each, plus the
                // warm-up) exceed the budget?
                let t = Instant::now();
                frame();
                let probe = t.elapsed();
                if probe * (self.args.samples as u32 + 3) > BUDGET {
                    let n = ((BUDGET.as_secs_f64() / probe.as_secs_f64()) as usize)
                        .clamp(1, MAX_MANUAL_FRAMES);
                    let t = Instant::now();
                    for _ in 1..n {
                        frame();
                    }
                    let mean = (probe + t.elapsed()).as_secs_f64() / n as f64;
                    println!(
                        "{group}/{function}/{}: {} per frame, mean of {n} frame(s) timed with \
                         Instant (criterion's {} samples would take over {} s)",
                        case.size,
                        fmt_time(mean),
                        self.args.samples,
                        BUDGET.as_secs()
                    );
                    self.record(
                        key,
                        Timed {
                            mean,
                            manual_frames: n,
                        },
                    );
                    continue;
                }
            }
            // criterion's own timing; the totals are a fallback when it writes no estimates
            // (test mode, --profile-time)
            let total = Rc::new(Cell::new((0u64, Duration::ZERO)));
            let acc = total.clone();
            g.bench_function(id, |b| {
                b.iter_custom(|iters| {
                    let d = if case.window == 0 {
                        let t = Instant::now();
                        for _ in 0..iters {
                            frame();
                        }
                        t.elapsed()
                    } else {
                        // the window's frames are timed; rebuilding and settling are not
                        let mut d = Duration::ZERO;
                        for _ in 0..iters {
                            if in_window == case.window {
                                // the old world freed before the new one is built, as a
                                // program builds its world once: built beside the old
                                // one, the new world's buffers landed wherever the old
                                // one's left room (a scattered heap, and a frame slower
                                // by up to 10 % on the side with more buffers)
                                frame = Box::new(|| {});
                                frame = (case.build)();
                                for _ in 0..case.settle {
                                    frame();
                                }
                                in_window = 0;
                            }
                            let t = Instant::now();
                            frame();
                            d += t.elapsed();
                            in_window += 1;
                        }
                        d
                    };
                    let (n, sum) = acc.get();
                    acc.set((n + iters, sum + d));
                    d
                })
            });
            drop(frame); // free a big world before the next one is built
            let (n, sum) = total.get();
            let mean = self
                .criterion_mean(group, &function, case.size)
                .or((n > 0).then(|| sum.as_secs_f64() / n as f64));
            if let Some(mean) = mean {
                self.record(
                    key,
                    Timed {
                        mean,
                        manual_frames: 0,
                    },
                );
            }
        }
        g.finish();
    }

    fn record(&mut self, key: Key, timed: Timed) {
        let row = (key.0, key.1, key.3);
        if !self.order.contains(&row) {
            self.order.push(row);
        }
        self.results.insert(key, timed);
    }

    fn get(
        &self,
        group: &'static str,
        variant: &'static str,
        side: Side,
        size: usize,
    ) -> Option<Timed> {
        self.results.get(&(group, variant, side, size)).copied()
    }
}

/// The contact scene's ratio measured interleaved: in each of [`INTERLEAVED_ROUNDS`]
/// rounds both worlds (KJOINT2 and the jointless reference) are built and settled
/// untimed, then their [`CONTACT_WINDOW`] frames timed one after the other, the order
/// alternating from round to round; printed: the medians of each side's frame and of the
/// rounds' ratios, with the ratios' quartiles. Criterion times the sides seconds apart, and
/// this machine's speed drifts by a few per cent over seconds: with a bound at 2× that
/// drift decided the rounded ratio. Id `contacts/interleaved/<groups>` for the filter.
fn contacts_interleaved(args: &Args, sizes: &Sizes) {
    let g = sizes.capsule_groups;
    if args.list || !args.matches(&format!("contacts/interleaved/{g}")) {
        return;
    }
    let scene = scenes::capsules_on_ground(g);
    let (rounds, frames) = if args.bench {
        (INTERLEAVED_ROUNDS, CONTACT_WINDOW)
    } else {
        (2, 1)
    };
    let settle = sizes.contact_settle;
    let timed = |frame: &mut dyn FnMut()| {
        for _ in 0..settle {
            frame();
        }
        let t = Instant::now();
        for _ in 0..frames {
            frame();
        }
        t.elapsed().as_secs_f64() / frames as f64
    };
    // each world dropped before the next is built (as in the criterion groups)
    let kjoint = || {
        let mut w = scene.kjoint();
        timed(&mut || w.frame())
    };
    let rapier = || {
        let mut w = scene.rapier();
        timed(&mut || w.frame())
    };
    let (mut k, mut p, mut ratio) = (Vec::new(), Vec::new(), Vec::new());
    for round in 0..rounds {
        let (tk, tp) = if round % 2 == 0 {
            let tk = kjoint();
            (tk, rapier())
        } else {
            let tp = rapier();
            (kjoint(), tp)
        };
        k.push(tk);
        p.push(tp);
        ratio.push(tk / tp);
    }
    println!(
        "\nContact scene interleaved ({rounds} rounds of {frames} frames a side, the order \
         alternating): KJOINT2 {} and the jointless reference {} a frame (medians); ratio \
         {:.2}× (median of the rounds; quartiles {:.2}–{:.2}×)",
        fmt_time(quantile(&mut k, 0.5)),
        fmt_time(quantile(&mut p, 0.5)),
        quantile(&mut ratio, 0.5),
        quantile(&mut ratio, 0.25),
        quantile(&mut ratio, 0.75),
    );
}

/// Rounds of the interleaved cost exponents ([`exponents_interleaved`]).
const EXPONENT_ROUNDS: usize = 7;

/// Simulated time each timed window of [`exponents_interleaved`] covers, as frames at the
/// small and the large size: about 0.2 s of the KJOINT2 side's work at each.
const EXPONENT_FRAMES: [usize; 2] = [100, 10];

/// The cost exponents of the chain, the pendulums and the tree inserted leaves first (511 →
/// 4095 joints) measured interleaved: in each of
/// [`EXPONENT_ROUNDS`] rounds, for each side, the small and the large world are built, run
/// [`scenes::SETTLE_FRAMES`] frames untimed (the first substep analyses the topology), then timed over
/// [`EXPONENT_FRAMES`] frames, one after the other, the order alternating from round to
/// round; printed: the median and quartiles of the rounds' exponents
/// `ln(t₂/t₁)/ln(n₂/n₁)` of each side. The table's exponents divide criterion's means at
/// the two sizes, timed a minute apart, and this machine's speed drifts by a few per cent
/// over that time: ±0.02 in an exponent. Id `exponents/interleaved/<scene>` (`chain`,
/// `pendulums`, `tree`).
fn exponents_interleaved(args: &Args, sizes: &Sizes) {
    // (id, label, the world at the small (0) or the large (1) size, the sizes in joints)
    type Make = Box<dyn Fn(usize) -> Scene>;
    let (chain, pendulums, depths) = (sizes.chain, sizes.pendulums, sizes.tree_leaves_first);
    let scenes: [(&str, &str, Make, [usize; 2]); 3] = [
        (
            "chain",
            "chain",
            Box::new(move |k| scenes::chain(chain[k])),
            chain,
        ),
        (
            "pendulums",
            "pendulums",
            Box::new(move |k| scenes::pendulums(pendulums[k])),
            pendulums,
        ),
        (
            "tree",
            "tree, leaves first",
            Box::new(move |k| scenes::tree(depths[k], TreeOrder::LeavesFirst)),
            depths.map(scenes::tree_size),
        ),
    ];
    let (rounds, frames) = if args.bench {
        (EXPONENT_ROUNDS, EXPONENT_FRAMES)
    } else {
        (1, [1, 1])
    };
    let mut printed = false;
    for (id, name, make, n) in scenes {
        if args.list || !args.matches(&format!("exponents/interleaved/{id}")) {
            continue;
        }
        // one world of size `k` (0 or 1) on `side`, built, run `SETTLE_FRAMES` untimed, then
        // timed (s a frame); dropped before the next is built
        let timed = |side: Side, k: usize, frames: usize| {
            let scene = make(k);
            let mut step: Stepper = match side {
                Side::Kjoint => {
                    let mut w = scene.kjoint();
                    Box::new(move || w.frame())
                }
                _ => {
                    let mut w = scene.rapier();
                    Box::new(move || w.frame())
                }
            };
            for _ in 0..scenes::SETTLE_FRAMES {
                step();
            }
            let t = Instant::now();
            for _ in 0..frames {
                step();
            }
            t.elapsed().as_secs_f64() / frames as f64
        };
        let ln_n = (n[1] as f64 / n[0] as f64).ln();
        let mut exponents = [Vec::new(), Vec::new()];
        for round in 0..rounds {
            for (e, side) in exponents.iter_mut().zip([Side::Kjoint, Side::Rapier]) {
                let (t1, t2) = if round % 2 == 0 {
                    let t1 = timed(side, 0, frames[0]);
                    (t1, timed(side, 1, frames[1]))
                } else {
                    let t2 = timed(side, 1, frames[1]);
                    (timed(side, 0, frames[0]), t2)
                };
                e.push((t2 / t1).ln() / ln_n);
            }
        }
        if !printed {
            println!(
                "\nCost exponents interleaved ({rounds} rounds; in each, both sizes of a side \
                 built and timed one after the other, the order alternating): median \
                 (quartiles) of the rounds"
            );
            printed = true;
        }
        let [k, p] = exponents.map(|mut v| {
            let (m, q1, q3) = (
                quantile(&mut v, 0.5),
                quantile(&mut v, 0.25),
                quantile(&mut v, 0.75),
            );
            format!("{m:.3} ({q1:.3}–{q3:.3})")
        });
        println!(
            "  {name:<20} {:>6} → {:<6}  KJOINT2 {k}   rapier {p}",
            n[0], n[1]
        );
    }
}

/// The value at fraction `f` of `v`'s values sorted (nearest rank; `v` is sorted).
fn quantile(v: &mut [f64], f: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * f).round() as usize]
}

fn fmt_time(s: f64) -> String {
    if s < 1e-3 {
        format!("{:.1} µs", s * 1e6)
    } else if s < 1.0 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{s:.2} s")
    }
}

fn fmt_timed(t: Option<Timed>) -> String {
    match t {
        None => "–".into(),
        Some(t) if t.manual_frames > 0 => format!("{} *", fmt_time(t.mean)),
        Some(t) => fmt_time(t.mean),
    }
}

/// The ratio table and the cost exponents.
fn report(r: &Runner, sizes: &Sizes) {
    if r.results.is_empty() {
        return;
    }
    let mode = if r.args.bench {
        "criterion means; * = mean of a few frames timed with Instant"
    } else {
        "TEST MODE: tiny sizes, one frame each, not a measurement"
    };
    println!("\nOne 60 Hz frame, KJOINT2 (4 substeps, Kn = 1e12) against rapier ({mode})\n");
    println!(
        "{:<34} {:>8} {:>12} {:>12} {:>9}",
        "scene", "size", "KJOINT2", "rapier", "ratio"
    );
    for &(group, variant, size) in &r.order {
        let k = r.get(group, variant, Side::Kjoint, size);
        let p = r.get(group, variant, Side::Rapier, size);
        let ratio = match (k, p) {
            // two decimals where the bound (2×) sits within the first one's rounding
            (Some(k), Some(p)) if group == "contacts" => format!("{:.2}×", k.mean / p.mean),
            (Some(k), Some(p)) => format!("{:.1}×", k.mean / p.mean),
            _ => "–".into(),
        };
        let name = match (group, variant) {
            ("contacts", _) => "contacts (ref. without joints)".to_string(),
            ("hub", _) => "hub (joints = size + 1)".to_string(),
            ("resting", _) => "resting pendulums, asleep".to_string(),
            (g, "") => g.to_string(),
            (g, v) => format!("{g} {}", v.replace('_', " ")),
        };
        println!(
            "{name:<34} {size:>8} {:>12} {:>12} {ratio:>9}",
            fmt_timed(k),
            fmt_timed(p)
        );
        if group == "contacts" {
            let others = [
                (Side::RapierJoints, "  rapier with its joints, 1/60 s"),
                (Side::RapierWritten, "  ref., bodies written each step"),
            ];
            for (side, label) in others {
                if let Some(o) = r.get(group, variant, side, size) {
                    let vs = k.map_or("–".into(), |k| format!("{:.2}×", k.mean / o.mean));
                    println!(
                        "{label:<34} {size:>8} {:>12} {:>12} {vs:>9}",
                        "",
                        fmt_timed(Some(o))
                    );
                }
            }
        }
    }
    println!("\nCost exponent log(t₂/t₁) / log(n₂/n₁) (n = joints):");
    let exponent = |group: &'static str, variant: &'static str, side: Side, n: [usize; 2]| match (
        r.get(group, variant, side, n[0]),
        r.get(group, variant, side, n[1]),
    ) {
        (Some(a), Some(b)) => format!(
            "{:.2}",
            (b.mean / a.mean).ln() / (n[1] as f64 / n[0] as f64).ln()
        ),
        _ => "–".into(),
    };
    let trees = |d: [u32; 2]| d.map(scenes::tree_size);
    let rows: [(&str, &'static str, &'static str, [usize; 2]); 4] = [
        ("chain", "chain", "", sizes.chain),
        ("pendulums", "pendulums", "", sizes.pendulums),
        (
            "tree, leaves first",
            "tree",
            "leaves_first",
            trees(sizes.tree_leaves_first),
        ),
        (
            "tree, root first",
            "tree",
            "root_first",
            trees(sizes.tree_root_first),
        ),
    ];
    for (label, group, variant, n) in rows {
        println!(
            "  {label:<20} {:>6} → {:<6}  KJOINT2 {:>5}   rapier {:>5}",
            n[0],
            n[1],
            exponent(group, variant, Side::Kjoint, n),
            exponent(group, variant, Side::Rapier, n)
        );
    }
}

/// Peak resident memory of the chain on both sides, each in a fresh process.
fn peak_memory(args: &Args, sizes: &Sizes) {
    let id = format!("peak_memory/chain/{}", sizes.memory_chain);
    if args.list || !args.matches(&id) {
        return;
    }
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            println!("peak memory: cannot find this executable: {e}");
            return;
        }
    };
    let run = |side: &str| -> Option<u64> {
        let out = std::process::Command::new(&exe)
            .env(
                MEMORY_ENV,
                format!("{side}:{}:{}", sizes.memory_chain, sizes.memory_frames),
            )
            .output()
            .ok()?;
        let text = String::from_utf8_lossy(&out.stdout);
        text.lines()
            .find_map(|l| l.strip_prefix("VmHWM_KIB "))
            .and_then(|v| v.trim().parse().ok())
    };
    let (base, k, p) = (run("baseline"), run("kjoint2"), run("rapier"));
    let mib = |v: Option<u64>| v.map_or("–".into(), |v| format!("{:.1} MiB", v as f64 / 1024.0));
    println!(
        "\nPeak resident memory (VmHWM), chain of {} built and stepped {} frame(s), fresh process each:",
        sizes.memory_chain, sizes.memory_frames
    );
    println!("  process baseline {}", mib(base));
    println!("  KJOINT2          {}", mib(k));
    println!("  rapier           {}", mib(p));
    if let (Some(b), Some(k), Some(p)) = (base, k, p) {
        let per = |v: u64| (v.saturating_sub(b)) as f64 * 1024.0 / sizes.memory_chain as f64;
        println!(
            "  ratio KJOINT2/rapier {:.1}× (above the baseline: {:.1}×; {:.1} KiB vs {:.1} KiB per joint)",
            k as f64 / p as f64,
            k.saturating_sub(b) as f64 / p.saturating_sub(b).max(1) as f64,
            per(k) / 1024.0,
            per(p) / 1024.0
        );
    }
}

/// A peak-memory child: `side:links:frames` → prints `VmHWM_KIB <n>`.
fn memory_child(spec: &str) {
    let parts: Vec<&str> = spec.split(':').collect();
    let side = parts.first().and_then(|s| MemorySide::parse(s));
    let links = parts.get(1).and_then(|s| s.parse().ok());
    let frames = parts.get(2).and_then(|s| s.parse().ok());
    match (side, links, frames) {
        (Some(side), Some(links), Some(frames)) => {
            if let Some(kib) = scenes::peak_memory_run(side, links, frames) {
                println!("VmHWM_KIB {kib}");
            }
        }
        _ => eprintln!("{MEMORY_ENV}={spec}: expected side:links:frames"),
    }
}

fn main() {
    if let Ok(spec) = std::env::var(MEMORY_ENV) {
        memory_child(&spec);
        return;
    }
    let args = Args::parse();
    let sizes = Sizes::new(args.bench);
    let mut c = Criterion::default()
        .sample_size(SAMPLES)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .configure_from_args();
    let mut r = Runner::new(args);

    let mut cases = Vec::new();
    for n in sizes.chain {
        cases.extend(pair("", n, 0, move || scenes::chain(n)));
    }
    r.group(&mut c, "chain", cases);

    let mut cases = Vec::new();
    for n in sizes.pendulums {
        cases.extend(pair("", n, 0, move || scenes::pendulums(n)));
    }
    r.group(&mut c, "pendulums", cases);

    // timed once both worlds have put the pendulums to sleep (0.5 s at rest)
    let n = sizes.resting;
    let resting = pair("", n, RESTING_SETTLE, move || scenes::resting_pendulums(n));
    r.group(&mut c, "resting", resting);

    let mut cases = Vec::new();
    for d in sizes.tree_leaves_first {
        let n = scenes::tree_size(d);
        cases.extend(pair("leaves_first", n, 0, move || {
            scenes::tree(d, TreeOrder::LeavesFirst)
        }));
    }
    for d in sizes.tree_root_first {
        let n = scenes::tree_size(d);
        cases.extend(pair("root_first", n, 0, move || {
            scenes::tree(d, TreeOrder::RootFirst)
        }));
    }
    r.group(&mut c, "tree", cases);

    let n = sizes.hub;
    r.group(&mut c, "hub", pair("", n, 0, move || scenes::hub(n)));

    let g = sizes.capsule_groups;
    let settle = sizes.contact_settle;
    let scene = Rc::new(LazyScene::new(move || scenes::capsules_on_ground(g)));
    let cases = [
        Side::Kjoint,
        Side::Rapier,
        Side::RapierJoints,
        Side::RapierWritten,
    ]
    .map(|side| lazy_case("", side, g, settle, CONTACT_WINDOW, scene.clone()));
    r.group(&mut c, "contacts", cases.into());

    r.group(
        &mut c,
        "urdf_arm",
        vec![
            Case {
                variant: "",
                side: Side::Kjoint,
                size: 3,
                settle: 0,
                window: 0,
                build: Box::new(|| {
                    let mut w = scenes::urdf_arm_kjoint();
                    Box::new(move || w.frame())
                }),
            },
            // rapier3d-urdf's own joints are f32 rapier only
            #[cfg(not(feature = "f64"))]
            Case {
                variant: "",
                side: Side::Rapier,
                size: 3,
                settle: 0,
                window: 0,
                build: Box::new(|| {
                    let mut w = scenes::urdf_arm_rapier();
                    Box::new(move || w.frame())
                }),
            },
        ],
    );

    r.group(
        &mut c,
        "four_bar",
        pair("", 4, 0, || scenes::four_bar(false)),
    );

    r.group(&mut c, "ring", pair("", 48, 0, || scenes::ring(48)));

    c.final_summary();
    report(&r, &sizes);
    contacts_interleaved(&r.args, &sizes);
    exponents_interleaved(&r.args, &sizes);
    peak_memory(&r.args, &sizes);
}
