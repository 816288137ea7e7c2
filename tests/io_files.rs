//! File formats of `dentbend::io`: `.npy` round trips and header layout, heat-map PNGs, 16- and
//! 8-bit height PNGs, and malformed files rejected with an error instead of a panic.

mod common;

use std::path::Path;

use common::TempDir;
use dentbend::io::{
    IoError, heatmap_rgb, read_height_png, read_npy_f32, write_heatmap_png, write_height_png16, write_npy_f32,
};

/// Deterministic test values spanning several magnitudes and signs.
fn values(n: usize) -> Vec<f32> {
    (0..n).map(|i| (i as f32 * 0.7368).sin() * 10f32.powi(i as i32 % 7 - 3)).collect()
}

#[test]
fn npy_round_trip_is_bit_exact() {
    let dir = TempDir::new("npy-round-trip");
    let mut data = values(3 * 5 * 2);
    data[0] = -0.0;
    data[1] = f32::INFINITY;
    data[2] = f32::NAN;
    data[3] = f32::MIN_POSITIVE / 8.0;
    data[4] = f32::MAX;
    for shape in [vec![3, 5, 2], vec![30], vec![15, 2], vec![1, 30, 1]] {
        let path = dir.path("a.npy");
        write_npy_f32(&path, &shape, &data).unwrap();
        let (read_shape, read) = read_npy_f32(&path).unwrap();
        assert_eq!(read_shape, shape);
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&read), bits(&data), "shape {shape:?}");
    }
    write_npy_f32(dir.path("scalar.npy"), &[], &[2.5]).unwrap();
    assert_eq!(read_npy_f32(dir.path("scalar.npy")).unwrap(), (vec![], vec![2.5]));
    write_npy_f32(dir.path("empty.npy"), &[0, 4], &[]).unwrap();
    assert_eq!(read_npy_f32(dir.path("empty.npy")).unwrap(), (vec![0, 4], vec![]));
}

#[test]
fn npy_header_is_aligned_numpy_dict() {
    let dir = TempDir::new("npy-header");
    for (shape, dims) in [(vec![4usize, 6], "(4, 6)"), (vec![24], "(24,)"), (vec![2, 3, 4], "(2, 3, 4)")] {
        let path = dir.path("h.npy");
        write_npy_f32(&path, &shape, &values(24)).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..6], b"\x93NUMPY");
        assert_eq!(&bytes[6..8], &[1, 0], "format version 1.0");
        let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        let data_offset = 10 + header_len;
        assert_eq!(data_offset % 64, 0, "data offset {data_offset} is not 64-byte aligned");
        assert_eq!(bytes.len(), data_offset + 4 * 24);
        let header = std::str::from_utf8(&bytes[10..data_offset]).unwrap();
        assert!(header.ends_with('\n'));
        assert_eq!(
            header.trim_end_matches(['\n', ' ']),
            format!("{{'descr': '<f4', 'fortran_order': False, 'shape': {dims}, }}")
        );
    }
}

#[test]
fn npy_rejects_shape_that_does_not_fit_data() {
    let dir = TempDir::new("npy-shape");
    let err = write_npy_f32(dir.path("x.npy"), &[3, 3], &[0.0; 8]).unwrap_err();
    assert!(matches!(err, IoError::InvalidArgument(_)), "{err}");
    assert!(!dir.path("x.npy").exists());
}

/// A version-1.0 `.npy` file with the given header text (padded) and payload bytes.
fn npy_bytes(header: &str, payload: &[u8]) -> Vec<u8> {
    let mut text = header.to_owned();
    while !(10 + text.len() + 1).is_multiple_of(64) {
        text.push(' ');
    }
    text.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(text.len() as u16).to_le_bytes());
    bytes.extend_from_slice(text.as_bytes());
    bytes.extend_from_slice(payload);
    bytes
}

#[test]
fn malformed_npy_files_are_errors() {
    let dir = TempDir::new("npy-malformed");
    let good = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 2), }";
    let sixteen = [0u8; 16];
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("empty", vec![]),
        ("bad magic", b"\x93NUMPZ\x01\x00\x10\x00{}".to_vec()),
        ("short", b"\x93NUMPY\x01".to_vec()),
        ("version 9", {
            let mut b = npy_bytes(good, &sixteen);
            b[6] = 9;
            b
        }),
        ("header past end", {
            let mut b = npy_bytes(good, &sixteen);
            b[8] = 0xff;
            b[9] = 0xff;
            b
        }),
        ("f8", npy_bytes("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 2), }", &[0; 32])),
        ("big endian", npy_bytes("{'descr': '>f4', 'fortran_order': False, 'shape': (2, 2), }", &sixteen)),
        ("fortran", npy_bytes("{'descr': '<f4', 'fortran_order': True, 'shape': (2, 2), }", &sixteen)),
        ("too few bytes", npy_bytes(good, &[0; 12])),
        ("too many bytes", npy_bytes(good, &[0; 20])),
        ("no shape", npy_bytes("{'descr': '<f4', 'fortran_order': False, }", &sixteen)),
        ("bad shape", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2, x), }", &sixteen)),
        ("negative dim", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (-2, 2), }", &sixteen)),
        (
            "huge shape",
            npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (99999999999, 99999999999), }", &sixteen),
        ),
        ("not a dict", npy_bytes("hello", &sixteen)),
        ("unterminated", npy_bytes("{'descr': '<f4", &sixteen)),
        ("non-utf8 header", {
            let mut b = npy_bytes(good, &sixteen);
            b[12] = 0xff;
            b
        }),
    ];
    for (name, bytes) in cases {
        let path = dir.path("bad.npy");
        std::fs::write(&path, &bytes).unwrap();
        match read_npy_f32(&path) {
            Err(IoError::Npy { path: p, message }) => {
                assert_eq!(p, path, "{name}");
                assert!(!message.is_empty(), "{name}");
            }
            other => panic!("{name}: expected a malformed-npy error, got {other:?}"),
        }
    }
    std::fs::write(dir.path("ok.npy"), npy_bytes(good, &sixteen)).unwrap();
    assert_eq!(read_npy_f32(dir.path("ok.npy")).unwrap(), (vec![2, 2], vec![0.0; 4]));
    let missing = read_npy_f32(dir.path("missing.npy")).unwrap_err();
    assert!(matches!(missing, IoError::Io { .. }), "{missing}");
    assert!(missing.to_string().contains("missing.npy"), "{missing}");
}

#[test]
fn heatmap_has_the_grid_dimensions_and_orientation() {
    let dir = TempDir::new("heatmap");
    let (w, h) = (7u32, 3u32);
    let mut data = vec![0.0f32; (w * h) as usize];
    data[0] = 2.0; // row 0, col 0: brightest, top-left
    data[(w + 3) as usize] = 1.0; // row 1, col 3: mid
    let path = dir.path("heat.png");
    write_heatmap_png(&path, &data, w, h, 2.0).unwrap();
    let picture = image::open(&path).unwrap();
    assert_eq!(picture.color(), image::ColorType::Rgb8);
    assert_eq!((picture.width(), picture.height()), (w, h));
    let rgb = picture.to_rgb8();
    let luma = |p: &image::Rgb<u8>| p.0.iter().map(|&c| u32::from(c)).sum::<u32>();
    assert_eq!(rgb.get_pixel(6, 2).0, [0, 0, 0], "zero is black");
    assert!(luma(rgb.get_pixel(0, 0)) > luma(rgb.get_pixel(3, 1)));
    assert!(luma(rgb.get_pixel(3, 1)) > 0);
    assert_eq!(rgb, heatmap_rgb(&data, w, h, 2.0).unwrap());
    // The ramp grows lighter all the way up: 0 to the maximum in 101 steps along a row.
    let row: Vec<f32> = (0..=100).map(|k| k as f32 / 100.0).collect();
    let ramp: Vec<u32> = heatmap_rgb(&row, 101, 1, 1.0).unwrap().pixels().map(luma).collect();
    assert!(ramp.windows(2).all(|w| w[1] >= w[0]), "{ramp:?}");
    // A zero maximum gives an all-dark picture.
    let dark = heatmap_rgb(&data, w, h, 0.0).unwrap();
    assert!(dark.pixels().all(|p| p.0 == [0, 0, 0]));
    // Size mismatches are errors.
    assert!(matches!(heatmap_rgb(&data, w, h + 1, 1.0), Err(IoError::InvalidArgument(_))));
    assert!(matches!(write_heatmap_png(dir.path("z.png"), &[], 0, 0, 1.0), Err(IoError::InvalidArgument(_))));
}

#[test]
fn height_png16_round_trip_within_quantization() {
    let dir = TempDir::new("height16");
    let (w, h) = (13u32, 9u32);
    let max = 0.37f32;
    let data: Vec<f32> = values((w * h) as usize).iter().map(|v| (v.abs() * 0.1).min(max)).collect();
    let path = dir.path("h16.png");
    write_height_png16(&path, &data, w, h, max).unwrap();
    assert_eq!(image::open(&path).unwrap().color(), image::ColorType::L16);
    let read = read_height_png(&path).unwrap();
    assert_eq!((read.width, read.height, read.values.len()), (w, h, data.len()));
    for (v, r) in data.iter().zip(&read.values) {
        assert!((v / max - r).abs() <= 1.0 / 65535.0, "{v} / {max} read back as {r}");
        assert!((0.0..=1.0).contains(r));
    }
    // Values beyond the maximum clamp to white, a zero maximum gives black.
    write_height_png16(&path, &[0.0, 1.0, 2.0, -1.0], 2, 2, 1.0).unwrap();
    assert_eq!(read_height_png(&path).unwrap().values, vec![0.0, 1.0, 1.0, 0.0]);
    write_height_png16(&path, &[0.0, 1.0, 2.0, -1.0], 2, 2, 0.0).unwrap();
    assert_eq!(read_height_png(&path).unwrap().values, vec![0.0; 4]);
    assert!(matches!(write_height_png16(&path, &[0.0; 3], 2, 2, 1.0), Err(IoError::InvalidArgument(_))));
}

#[test]
fn height_png8_gray_alpha_and_rgb_read_as_luma() {
    let dir = TempDir::new("height8");
    let (w, h) = (17u32, 5u32);
    let gray = image::GrayImage::from_fn(w, h, |x, y| image::Luma([((x * 37 + y * 11) % 256) as u8]));
    let path = dir.path("h8.png");
    gray.save(&path).unwrap();
    let read = read_height_png(&path).unwrap();
    assert_eq!((read.width, read.height), (w, h));
    for (p, r) in gray.pixels().zip(&read.values) {
        assert!((f32::from(p.0[0]) / 255.0 - r).abs() <= 1.0 / 255.0 * 1e-3);
    }

    let gray_alpha = image::GrayAlphaImage::from_fn(2, 1, |x, _| image::LumaA([if x == 0 { 51 } else { 255 }, 0]));
    gray_alpha.save(dir.path("ga.png")).unwrap();
    assert_eq!(read_height_png(dir.path("ga.png")).unwrap().values, vec![0.2, 1.0]);

    let rgb = image::RgbImage::from_fn(3, 1, |x, _| image::Rgb([[255, 0, 0], [0, 0, 0], [255, 255, 255]][x as usize]));
    rgb.save(dir.path("rgb.png")).unwrap();
    let v = read_height_png(dir.path("rgb.png")).unwrap().values;
    assert!((v[0] - 0.2126).abs() < 2.0 / 255.0, "red luma {}", v[0]);
    assert_eq!(&v[1..], &[0.0, 1.0]);
}

#[test]
fn malformed_png_files_are_errors() {
    let dir = TempDir::new("png-malformed");
    let write = |name: &str, bytes: &[u8]| {
        let p = dir.path(name);
        std::fs::write(&p, bytes).unwrap();
        p
    };
    let garbage = write("garbage.png", b"this is not a picture at all, just some text");
    let empty = write("empty.png", b"");
    let good = dir.path("good.png");
    write_height_png16(&good, &values(64 * 64), 64, 64, 1.0).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    let truncated = write("truncated.png", &bytes[..bytes.len() / 2]);
    let mut corrupt_bytes = bytes.clone();
    for b in &mut corrupt_bytes[60..120] {
        *b ^= 0x5a;
    }
    let corrupt = write("corrupt.png", &corrupt_bytes);
    for path in [&garbage, &empty, &truncated, &corrupt] {
        let err = read_height_png(path).unwrap_err();
        assert!(err.to_string().contains(path.file_name().unwrap().to_str().unwrap()), "{err}");
    }
    let missing = read_height_png(Path::new(&dir.path("nope.png"))).unwrap_err();
    assert!(matches!(missing, IoError::Io { .. }), "{missing}");
    assert!(read_height_png(&good).is_ok());
}
