//! What a table read may hold (`pipeline::table::CsvText`): the saturated relative error the
//! metrics write (a reference that is zero everywhere) is a table's value, not a corruption.
//! Corrupt cells are refused through the binary (`tests/outputs_and_names.rs`).

use crate::pipeline::table::CsvText;
use std::path::Path;

#[test]
fn a_saturated_relative_error_is_a_tables_value() {
    let table = "map,encoder,domain,effects,metric,rmse,rel_rmse,neg_frac\n\
                 m,sh1,sphere,,exact,0.5,0.1,0\nm,sh2,sphere,,exact,BAD,0.1,0\n";
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.csv");
    std::fs::write(&path, table.replace("BAD", "0.25").replace(",0.1,0\nm,sh2", ",1.7976931348623157e308,0\nm,sh2"))
        .unwrap();
    let t = CsvText::parse(&std::fs::read(&path).unwrap(), Path::new("t.csv"));
    assert!(t.is_ok(), "{t:?}");
}
