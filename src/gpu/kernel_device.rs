//! Choosing between the GPU kernels and their CPU twins (`DENTBEND_BACKEND=cpu|gpu|auto`).

use std::sync::OnceLock;

use super::{GpuContext, GpuError};

/// Where the dent kernels run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum KernelDevice {
    /// The CPU twins.
    Cpu,
    /// The WGSL kernels; an error when no adapter exists.
    Gpu,
    /// The GPU when an adapter exists, else the CPU twins with one notice.
    #[default]
    Auto,
}

impl KernelDevice {
    /// Parses `cpu`, `gpu` or `auto` (any case).
    ///
    /// # Errors
    /// [`GpuError::BadBackend`].
    pub fn parse(text: &str) -> Result<Self, GpuError> {
        match text.trim().to_ascii_lowercase().as_str() {
            "cpu" => Ok(Self::Cpu),
            "gpu" => Ok(Self::Gpu),
            "auto" | "" => Ok(Self::Auto),
            _ => Err(GpuError::BadBackend(text.into())),
        }
    }

    /// The backend `DENTBEND_BACKEND` names, `Auto` when unset.
    ///
    /// # Errors
    /// [`GpuError::BadBackend`].
    pub fn from_env() -> Result<Self, GpuError> {
        std::env::var("DENTBEND_BACKEND").map_or(Ok(Self::Auto), |v| Self::parse(&v))
    }

    /// The GPU context this backend runs on: `None` for `Cpu`, and for `Auto` without an adapter
    /// (printing one notice per process).
    ///
    /// # Errors
    /// For `Gpu`, why no device could be created.
    pub fn context(self) -> Result<Option<&'static GpuContext>, GpuError> {
        match self {
            Self::Cpu => Ok(None),
            Self::Gpu => shared_context().map(Some).map_err(Clone::clone),
            Self::Auto => match shared_context() {
                Ok(context) => Ok(Some(context)),
                Err(error) => {
                    static NOTICE: OnceLock<()> = OnceLock::new();
                    NOTICE.get_or_init(|| log::warn!("{error}; running the CPU kernels instead"));
                    Ok(None)
                }
            },
        }
    }
}

/// The process-wide GPU context, created on first use.
///
/// # Errors
/// Why no device could be created (the same error on every call).
pub fn shared_context() -> Result<&'static GpuContext, &'static GpuError> {
    static CONTEXT: OnceLock<Result<GpuContext, GpuError>> = OnceLock::new();
    CONTEXT.get_or_init(GpuContext::new).as_ref()
}
