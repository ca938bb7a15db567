//! Nothing a user types crashes or hangs the solver: seeded mutations of the scenes in
//! `scenes/` and of the corpus `tests/fuzz-corpus/` (wrong types, NaN, infinities, huge,
//! tiny and negative numbers, swapped corners, truncation, binary garbage, odd line endings
//! and names) go through the parser and validation, and every accepted one that is small
//! through set-up and a few CPU steps. Each rejected input must name a field and a reason;
//! nothing may panic; a run must end (a fault is an answer). `MESHFREE_FUZZ_CASES` sets the
//! count (default 10,000) and `MESHFREE_FUZZ_SEED` the seed.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::time::Instant;

use meshfree_core::backend::{self, BackendChoice};
use meshfree_core::scene::estimate::estimate;
use meshfree_core::scene::{Scene, SceneError};
use meshfree_core::solver::step::Stepper;

/// xorshift64*: small, seeded, the same sequence on every machine.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }
}

const NUMBERS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "1e300",
    "-1e300",
    "1e-300",
    "0",
    "-0.0",
    "-1",
    "1e39",
    "1e-40",
    "1e-12",
    "1e12",
    "4294967296",
    "-4294967296",
    "9223372036854775807",
    "1e20",
    "0.5",
    "3",
    "1e-6",
    "2147483648",
];
const VALUES: &[&str] = &[
    "\"text\"",
    "true",
    "[]",
    "[1.0]",
    "[1.0, 2.0, 3.0, 4.0]",
    "{}",
    "\"\"",
    "[\"a\"]",
    "{ x = 1 }",
    "1979-05-27",
];
const NAMES: &[&str] = &[
    "\"a\\u0000b\"",
    "\"two\\nlines\"",
    "\"../up\"",
    "\"/abs\"",
    "\".\"",
    "\"\"",
    "\" \"",
    "\"\\u00e9t\\u00e9\"",
    "\"a/b\"",
];

/// Byte ranges of the number tokens of `text` (after `=`, `[` or `,`).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = (b[i].is_ascii_digit() || b[i] == b'-')
            && i > 0
            && matches!(b[i - 1], b' ' | b'[' | b'=' | b',');
        if starts {
            let j = (i + 1..b.len())
                .find(|&j| {
                    !(b[j].is_ascii_alphanumeric() || matches!(b[j], b'.' | b'-' | b'+' | b'_'))
                })
                .unwrap_or(b.len());
            out.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// One mutation of `text`.
fn mutate(text: &str, rng: &mut Rng) -> Vec<u8> {
    let lines: Vec<&str> = text.lines().collect();
    let nums = numbers(text);
    match rng.below(12) {
        // A number replaced by an extreme one (three times as often as the others: most
        // crashes were numbers).
        0..=2 if !nums.is_empty() => {
            let (a, b) = *rng.pick(&nums);
            format!("{}{}{}", &text[..a], rng.pick(NUMBERS), &text[b..]).into_bytes()
        }
        3 if !nums.is_empty() => {
            let (a, b) = *rng.pick(&nums);
            format!("{}{}{}", &text[..a], rng.pick(VALUES), &text[b..]).into_bytes()
        }
        // A line's value replaced, or the line dropped or doubled.
        4 => {
            let k = rng.below(lines.len());
            let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
            match rng.below(3) {
                0 => {
                    if let Some((key, _)) = out[k].split_once('=') {
                        out[k] = format!("{key}= {}", rng.pick(VALUES));
                    }
                }
                1 => {
                    out.remove(k);
                }
                _ => out.insert(k, lines[k].to_string()),
            }
            out.join("\n").into_bytes()
        }
        // The corners of a box swapped (min > max).
        5 => text
            .replacen("min =", "tmp_min =", 1)
            .replacen("max =", "min =", 1)
            .replacen("tmp_min =", "max =", 1)
            .into_bytes(),
        // Truncated.
        6 => text.as_bytes()[..rng.below(text.len())].to_vec(),
        // Binary garbage spliced in.
        7 => {
            let mut b = text.as_bytes().to_vec();
            let at = rng.below(b.len());
            let garbage: Vec<u8> = (0..1 + rng.below(16)).map(|_| rng.next() as u8).collect();
            b.splice(at..at, garbage);
            b
        }
        // Line endings: CR only, CRLF, or none.
        8 => match rng.below(3) {
            0 => text.replace('\n', "\r").into_bytes(),
            1 => text.replace('\n', "\r\n").into_bytes(),
            _ => text.replace('\n', " ").into_bytes(),
        },
        // An odd name.
        9 => {
            let name = if rng.below(4) == 0 {
                format!("\"{}\"", "n".repeat(300))
            } else {
                rng.pick(NAMES).to_string()
            };
            let out: Vec<String> = lines
                .iter()
                .map(|l| {
                    if l.starts_with("name =") {
                        format!("name = {name}")
                    } else {
                        l.to_string()
                    }
                })
                .collect();
            out.join("\n").into_bytes()
        }
        // Two numbers at once (a block and its domain, a spacing and a time).
        _ if nums.len() >= 2 => {
            let mut t = text.to_string();
            for _ in 0..2 {
                let n = numbers(&t);
                let (a, b) = *rng.pick(&n);
                t = format!("{}{}{}", &t[..a], rng.pick(NUMBERS), &t[b..]);
            }
            t.into_bytes()
        }
        _ => text.as_bytes().to_vec(),
    }
}

/// Most particles of an accepted mutant that is also set up and stepped.
const RUN_UP_TO: f64 = 12_000.0;
/// Steps of each such run.
const STEPS: u64 = 3;

/// What one input did; a panic is caught and reported with its input.
fn exercise(bytes: &[u8]) -> Result<&'static str, String> {
    let Ok(text) = std::str::from_utf8(bytes) else {
        // What `Scene::from_file` says of a file that is not UTF-8: an error, never a panic.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("fuzz.toml");
        std::fs::write(&path, bytes).unwrap();
        return match Scene::from_file(&path) {
            Err(e) if !e.to_string().trim().is_empty() => Ok("refused (not UTF-8)"),
            Err(_) => Err("an empty error for a file that is not UTF-8".into()),
            Ok(_) => Ok("accepted"),
        };
    };
    let scene = match Scene::from_toml(text, "fuzz.toml") {
        Err(e) => {
            let field_named = match &e {
                SceneError::Parse { field, reason, .. }
                | SceneError::Invalid { field, reason, .. } => {
                    !field.trim().is_empty() && !reason.trim().is_empty()
                }
                _ => !e.to_string().trim().is_empty(),
            };
            return if field_named {
                Ok("refused")
            } else {
                Err(format!("an error without field or reason: {e:?}"))
            };
        }
        Ok(s) => s,
    };
    let e = estimate(&scene.file);
    if e.particles > RUN_UP_TO {
        return Ok("accepted (large: not run)");
    }
    let setup = match scene.setup() {
        Ok(s) => s,
        Err(e) if !e.to_string().trim().is_empty() => return Ok("refused at set-up"),
        Err(e) => return Err(format!("an empty set-up error: {e:?}")),
    };
    if setup.particles.is_empty() {
        return Ok("accepted (no particles)");
    }
    let mut solver = backend::create(BackendChoice::Cpu, backend::Layout::One, setup)
        .map_err(|e| e.to_string())?;
    let mut stepper = Stepper::new(scene.gates()).with_end(scene.file.time.end);
    let t_end = scene.file.time.end;
    let mut taken = 0;
    while taken < STEPS {
        match stepper.batch(&mut *solver, t_end, STEPS - taken) {
            Ok(b) if b.steps == 0 => break,
            Ok(b) => taken += b.steps,
            Err(_) => return Ok("ran: a fault"),
        }
    }
    Ok("ran")
}

fn corpus() -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for dir in [root.join("../scenes"), root.join("tests/fuzz-corpus")] {
        let mut files: Vec<_> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .collect();
        files.sort();
        for p in files {
            out.push((
                p.display().to_string(),
                std::fs::read_to_string(&p).unwrap(),
            ));
        }
    }
    out
}

#[test]
fn mutated_scenes_never_panic_hang_or_fail_silently() {
    let cases: usize = std::env::var("MESHFREE_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10_000);
    let seed: u64 = std::env::var("MESHFREE_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x5eed_2026);
    let corpus = corpus();
    assert!(corpus.len() >= 10, "{} corpus files", corpus.len());
    // Quiet panics: each is caught and reported with its input below.
    std::panic::set_hook(Box::new(|_| {}));
    let mut rng = Rng(seed | 1);
    let mut tally = std::collections::BTreeMap::<&str, usize>::new();
    let mut failures = Vec::new();
    let started = Instant::now();
    for case in 0..cases {
        let (origin, text) = rng.pick(&corpus);
        let mut bytes = mutate(text, &mut rng);
        if rng.below(3) == 0 {
            // A second mutation on a third of the inputs.
            if let Ok(t) = String::from_utf8(bytes.clone()) {
                bytes = mutate(&t, &mut rng);
            }
        }
        let one = Instant::now();
        match catch_unwind(AssertUnwindSafe(|| exercise(&bytes))) {
            Ok(Ok(what)) => *tally.entry(what).or_default() += 1,
            Ok(Err(why)) => failures.push(format!("case {case} ({origin}): {why}")),
            Err(p) => {
                let msg = p
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                failures.push(format!(
                    "case {case} ({origin}): panicked: {msg}\n--- input ---\n{}",
                    String::from_utf8_lossy(&bytes)
                ));
            }
        }
        let took = one.elapsed().as_secs_f64();
        if took > 10.0 {
            failures.push(format!(
                "case {case} ({origin}): took {took:.1} s (a hang?)\n--- input ---\n{}",
                String::from_utf8_lossy(&bytes)
            ));
        }
        if failures.len() >= 5 {
            break;
        }
    }
    let _ = std::panic::take_hook();
    eprintln!(
        "{cases} inputs in {:.1} s: {tally:?}",
        started.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    let ran =
        tally.get("ran").copied().unwrap_or(0) + tally.get("ran: a fault").copied().unwrap_or(0);
    assert!(
        ran * 10 >= cases,
        "only {ran} of {cases} inputs ran: the mutations are too harsh to test the solver"
    );
}
