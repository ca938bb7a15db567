//! The reference data the cases measure against: the files of the repository's `refdata/`
//! (each citing its source), compiled in so the binary runs anywhere, and the reader of their
//! CSV rows.

/// Read `name` from `refdata/` (compiled in, so the binary runs anywhere).
pub fn refdata(name: &str) -> &'static str {
    match name {
        "dambreak_martin_moyce_n1_surge_and_height.csv" => {
            include_str!("../../../refdata/dambreak_martin_moyce_n1_surge_and_height.csv")
        }
        "dambreak_koshizuka_oka_1996_surge_front.csv" => {
            include_str!("../../../refdata/dambreak_koshizuka_oka_1996_surge_front.csv")
        }
        "analytic_poiseuille_couette_startup_profiles.csv" => {
            include_str!("../../../refdata/analytic_poiseuille_couette_startup_profiles.csv")
        }
        "cylinder_strouhal_vs_Re.csv" => {
            include_str!("../../../refdata/cylinder_strouhal_vs_Re.csv")
        }
        "analytic_taylor_green_decay.csv" => {
            include_str!("../../../refdata/analytic_taylor_green_decay.csv")
        }
        "elastic_gray2001_oscillating_plate.json" => {
            include_str!("../../../refdata/elastic_gray2001_oscillating_plate.json")
        }
        "fsi_antoci2007_elastic_gate.json" => {
            include_str!("../../../refdata/fsi_antoci2007_elastic_gate.json")
        }
        "fsi_antoci2007_elastic_gate.csv" => {
            include_str!("../../../refdata/fsi_antoci2007_elastic_gate.csv")
        }
        _ => panic!("unknown refdata file {name}"),
    }
}

/// The rows of a refdata CSV (comment lines starting with '#' and the header skipped).
pub fn csv_rows(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .skip(1)
        .map(|l| l.split(',').map(|f| f.trim().to_string()).collect())
        .collect()
}
