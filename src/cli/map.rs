//! `rubsim map`: the 2-D map of `[run.map]` — speed × a scene key, or two scene keys at the
//! scene's speed — run as the cases of one study ([`rubsim::study`]: the same expansion into
//! variants × speeds as a sweep, the same case files, shards and merge) and assembled by
//! [`rubsim::study::assemble`]; here, what it prints of the map.

use rubsim::analysis::SpeedResults;
use rubsim::study::summary::{regime_cells, MapRecord};

/// Prints the map's size and its count of cells per regime.
pub fn report(map: &MapRecord, runs: &[SpeedResults]) {
    println!(
        "map {} × {}: {} cases",
        map.x.values.len(),
        map.y.values.len(),
        runs.len()
    );
    for (name, n) in regime_cells(runs) {
        println!("  {name:>27}  {n} cells");
    }
}
