//! Python bindings of dentbend: the `dentbend._dentbend` extension module, which the `dentbend`
//! package (python/dentbend) re-exports.
//!
//! - Arrays come in as numpy arrays (or anything `numpy.asarray` takes): positions `(N, 3)`
//!   float32, faces `(M, 3)` uint32. Arrays already of that dtype and C-contiguous are read in
//!   place; other float and integer arrays are converted once (positions rounded to float32,
//!   faces range-checked), other dtypes refused.
//! - Results go out as new numpy arrays that own the library's output (no second copy).
//! - The interpreter lock is released while the library works, so other Python threads run.
//! - Every refused value raises `dentbend.DentError` (a `ValueError`) with the library's
//!   message (an argument of the wrong Python type raises `TypeError`, as Python's own
//!   functions do); nothing the caller passed is modified.

mod arrays;
mod damage;
mod dent;
mod fracture;
mod replica;

use pyo3::prelude::*;

pyo3::create_exception!(
    dentbend,
    DentError,
    pyo3::exceptions::PyValueError,
    "An input dentbend refuses (wrong shape or dtype, NaN, an index out of range, a dent the \
     impact cannot make), with the library's message; nothing was changed."
);

/// The extension module.
#[pymodule]
fn _dentbend(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("DentError", m.py().get_type::<DentError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(dent::dent, m)?)?;
    m.add_function(wrap_pyfunction!(dent::rust_dent_seconds, m)?)?;
    m.add_class::<dent::DentResult>()?;
    m.add_class::<damage::Mesh>()?;
    m.add_class::<damage::BodyState>()?;
    m.add_class::<damage::Hit>()?;
    m.add_class::<damage::AppliedDent>()?;
    m.add_class::<damage::Damage>()?;
    m.add_class::<fracture::Fracture>()?;
    m.add_class::<fracture::Piece>()?;
    m.add_class::<fracture::ReplicaFracture>()?;
    m.add_class::<replica::Replica>()?;
    Ok(())
}
