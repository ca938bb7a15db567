//! A scene file that costs far more to read than its size is refused before it is parsed,
//! naming the file and the reason (issue #52: 4.3 MB of dotted tables took 1.15 GB;
//! `/dev/zero` filled memory before it was refused).

use meshfree_core::scene::input_limits::{self, count};
use meshfree_core::scene::Scene;

#[test]
fn a_file_larger_than_the_cap_is_refused_after_reading_at_most_the_cap() {
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.toml");
    let mut text = Scene::builtin("tank-2d").unwrap().text;
    text += &"# padding\n".repeat(input_limits::MAX_BYTES / 10 + 1);
    std::fs::write(&big, &text).unwrap();
    let e = Scene::from_file(&big).unwrap_err();
    assert!(
        e.to_string().starts_with(&format!(
            "{}: the file is larger than 16 MiB",
            big.display()
        )),
        "{e}"
    );
    // An endless file: refused without reading past the cap (else this never ends).
    if std::path::Path::new("/dev/zero").exists() {
        let e = Scene::from_file("/dev/zero").unwrap_err();
        assert!(e.to_string().contains("larger than 16 MiB"), "{e}");
    }
    // And text handed in directly.
    let e = Scene::from_toml(&text, "big text").unwrap_err();
    assert_eq!(e.field(), Some("(document)"), "{e}");
}

#[test]
fn dotted_tables_are_counted_and_refused_before_parsing() {
    // 1.2 MB of dotted keys: 350,000 tables (7 a line), about 350 MB once parsed.
    let text: String = (0..50_000)
        .map(|i| format!("a{i}.b.c.d.e.f.g.h = 1\n"))
        .collect();
    let e = Scene::from_toml(&text, "dotted.toml").unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.starts_with("dotted.toml: (document): the file holds 350000 tables"),
        "{msg}"
    );
    // Values: a long array of numbers.
    let text = format!("a = [{}]\n", "1,".repeat(input_limits::MAX_VALUES));
    let e = Scene::from_toml(&text, "numbers.toml").unwrap_err();
    assert!(e.to_string().contains("values"), "{e}");
}

#[test]
fn the_count_skips_strings_and_comments_and_reads_headers_and_inline_tables() {
    let c = count(
        "name = \"a.b.c [x] {y}\" # c.d [e] {f}\n\
         [t.u]\n\
         k.l = 1.5\n\
         v = [1, 2.5, {p.q = 'r.s'}]\n\
         [[w]]\n\
         s = '''x.y\n[z]\n{'''\n",
    );
    // Tables: [t.u] (2), k.l (1), {p.q} (1 + 1), [[w]] (1).
    assert_eq!(c.tables, 6, "{c:?}");
    // Values: name, k.l, v, the array, its two commas, p.q, s.
    assert_eq!(c.values, 8, "{c:?}");
    // Every built-in scene is far within the limits.
    for name in meshfree_core::scene::builtin_names() {
        let c = count(&Scene::builtin(name).unwrap().text);
        assert!(c.tables < 100 && c.values < 1000, "{name}: {c:?}");
    }
}
