//! The kernel table (`kernels.rs`) against the PTX that `build.rs` keeps: every entry with
//! its parameters, and the lane counts.

use super::*;
use std::collections::BTreeSet;

/// The PTX of every module (the fatbins' copies are compressed; build.rs keeps these).
mod ptx {
    include!(concat!(env!("OUT_DIR"), "/ptx_text.rs"));
}

/// The parameter list of entry `name` in PTX `text`, as the kinds of its parameters:
/// "b8[size]" (a struct by value), "u32", "f32", "u64" (a pointer).
fn ptx_params(text: &str, name: &str) -> Option<Vec<String>> {
    let start = text.find(&format!(".entry {name}("))?;
    let list = &text[start..start + text[start..].find(')')?];
    Some(
        list.lines()
            .filter_map(|l| l.trim().strip_prefix(".param "))
            .map(|p| {
                let w: Vec<&str> = p.split_whitespace().collect();
                match w.as_slice() {
                    [".align", _, ".b8", arr] => {
                        let size = arr
                            .split('[')
                            .nth(1)
                            .unwrap_or("")
                            .trim_end_matches([']', ',']);
                        format!("b8[{size}]")
                    }
                    [ty, ..] => ty.trim_start_matches('.').to_string(),
                    [] => String::new(),
                }
            })
            .collect(),
    )
}

/// The parameter kinds a C signature gives in PTX: "u64" (a pointer), "b8[size]"
/// (SphParams by value), "u32" (unsigned), "f32" (float).
fn c_params(signature: &str) -> Vec<String> {
    signature
        .split(',')
        .map(|a| {
            let a = a.trim();
            if a.contains('*') {
                "u64".to_string()
            } else if a.starts_with("const SphParams") {
                format!("b8[{}]", std::mem::size_of::<SphParams>())
            } else if a.starts_with("unsigned long long ") {
                "u64".to_string()
            } else if a.starts_with("unsigned ") {
                "u32".to_string()
            } else if a.starts_with("float ") {
                "f32".to_string()
            } else {
                panic!("no PTX kind for `{a}`")
            }
        })
        .collect()
}

/// Every entry the table names is in its module's PTX with the table's parameters (so the
/// SAFETY comments of launch/, which go by the table, hold argument for argument: count,
/// pointer or not, and SphParams by value at Rust's size); and every entry of the PTX is
/// in the table.
#[test]
fn table_matches_ptx() {
    if ptx::PTX_TEXT.is_empty() {
        println!("SKIPPED: this build carries no PTX (no nvcc at build time)");
        return;
    }
    for (module, text) in ptx::PTX_TEXT {
        let in_ptx: BTreeSet<String> = text
            .lines()
            .filter_map(|l| l.strip_prefix(".visible .entry "))
            .map(|l| l.trim_end_matches('(').to_string())
            .collect();
        let mut in_table = BTreeSet::new();
        for f in Family::ALL
            .into_iter()
            .filter(|f| f.spec().module == *module)
        {
            let want = c_params(f.spec().signature);
            for dim in [2, 3] {
                for name in f.entries(dim) {
                    let got = ptx_params(text, &name).unwrap_or_else(|| {
                        panic!("{f:?}: entry `{name}` is not in module `{module}`")
                    });
                    assert_eq!(got, want, "{f:?}: the parameters of `{name}`");
                    in_table.insert(name);
                }
            }
        }
        assert_eq!(
            in_ptx, in_table,
            "module `{module}`: the PTX's entries (left) and the table's (right)"
        );
    }
    for (i, f) in Family::ALL.into_iter().enumerate() {
        assert_eq!(f as usize, i, "Family::ALL is out of order at {f:?}");
    }
}

#[test]
fn lane_counts_are_the_powers_of_two_to_the_maximum() {
    assert_eq!(LANE_COUNTS.first(), Some(&1));
    assert_eq!(LANE_COUNTS.last().copied(), Some(MF_LANES_MAX as usize));
    assert!(LANE_COUNTS.windows(2).all(|w| w[1] == 2 * w[0]));
}
