// envelope_cols: placeholder being replaced by its kernel; dispatch geometry documented there.
@compute @workgroup_size(1)
fn main() {}
