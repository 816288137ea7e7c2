//! The committed C header is what cbindgen makes from the crate now: a change to the API that
//! is not in `include/dentbend.h` fails here (`DENTBEND_BLESS=1` writes the new header).

use std::path::Path;

#[test]
fn the_committed_header_is_up_to_date() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_crate(crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header");
    let mut made = Vec::new();
    bindings.write(&mut made);
    let path = crate_dir.join("include/dentbend.h");
    if std::env::var_os("DENTBEND_BLESS").is_some() {
        std::fs::write(&path, &made).expect("write the header");
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == made,
        "include/dentbend.h is stale: regenerate it with `DENTBEND_BLESS=1 cargo test -p dentbend-c --test header`"
    );
}
