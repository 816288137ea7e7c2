//! `--backend cpu|gpu|auto`: the same dent maps and dented meshes from the GPU kernels, and
//! pictures from the GPU renderer.

use clap::{Args, ValueEnum};
use dentbend::damage::DentBackend;
use dentbend::dent::{BatchOutcome, DentJob, DentStages, dent_batch_tracked, plan_dent};
use dentbend::gpu::{GpuBackend, GpuContext, GpuDenter, KernelDevice};
use dentbend::mesh::Refinement;
use dentbend::{DentError, DentParams, DentReport, Impact, TriMesh};
use dentbend_solver::render::Renderer;

use crate::error::CliError;

/// Where the kernels run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BackendChoice {
    /// The CPU kernels.
    Cpu,
    /// The WGSL kernels (an error without a GPU adapter).
    Gpu,
    /// The GPU when an adapter exists, else the CPU (one notice).
    Auto,
}

/// The `--backend` flag.
#[derive(Debug, Args)]
pub struct BackendOption {
    /// Where the dent kernels and pictures run [default: $DENTBEND_BACKEND, else cpu]
    #[arg(long, value_enum)]
    pub backend: Option<BackendChoice>,
}

impl BackendOption {
    /// The backend the flag, else `DENTBEND_BACKEND`, else `cpu` selects.
    pub fn backend(&self) -> Result<KernelDevice, CliError> {
        Ok(match self.backend {
            Some(BackendChoice::Cpu) => KernelDevice::Cpu,
            Some(BackendChoice::Gpu) => KernelDevice::Gpu,
            Some(BackendChoice::Auto) => KernelDevice::Auto,
            // The command line opts in to the GPU: an adapter's driver may print to stderr.
            None if std::env::var_os("DENTBEND_BACKEND").is_none() => KernelDevice::Cpu,
            None => KernelDevice::from_env().map_err(|e| CliError::Usage(e.to_string()))?,
        })
    }

    /// The GPU context to use, or `None` for the CPU kernels.
    pub fn context(&self) -> Result<Option<&'static GpuContext>, CliError> {
        self.backend()?.context().map_err(|e| CliError::Usage(e.to_string()))
    }

    /// The renderer of pictures: the GPU one for `gpu` (an error without an adapter) and for
    /// `auto` when an adapter exists, else the CPU rasterizer.
    pub fn renderer(&self) -> Result<Renderer<'static>, CliError> {
        Renderer::from_backend(self.backend()?).map_err(|e| CliError::Usage(e.to_string()))
    }

    /// The flag as given, to pass on to another command line (`None` when absent).
    pub fn flag(&self) -> Option<String> {
        let choice = self.backend?.to_possible_value()?;
        Some(format!("--backend {}", choice.get_name()))
    }
}

/// Every stage of one dent map, computed on the GPU (`target_edge` as for `dent_map_stages`).
pub fn gpu_stages(
    context: &GpuContext,
    projectile: &TriMesh,
    impact: &Impact,
    params: &DentParams,
) -> Result<DentStages, CliError> {
    let plan = plan_dent(projectile, impact, params, None)?;
    let denter = GpuDenter::new(context, &[]).map_err(gpu_error)?;
    let job = DentJob { target: 0, projectile, impact: *impact, params: params.clone() };
    let stages = denter.stages_from_plans(&[job], &[plan]).map_err(gpu_error)?;
    let stages = stages.into_iter().next().expect("one job, one result").into_stages();
    // The checks `dent_map_stages` makes on the CPU.
    if !stages.zbuffer.iter().any(|&p| p > 0.0) || !stages.smoothed.iter().any(|&h| h > 0.0) {
        return Err(CliError::Dent(dentbend::DentError::EmptyProfile));
    }
    if stages.map.cells.iter().flatten().any(|v| !v.is_finite()) {
        return Err(CliError::Usage("--dent-distance is too large for f32 arithmetic".into()));
    }
    Ok(stages)
}

/// What [`dent_pair_or_one`] did to the target: its report, the vertices that moved and what
/// refinement appended (for the target's per-vertex data).
pub struct TargetDent {
    /// The target's dent report.
    pub report: DentReport,
    /// The target's vertices that moved, ascending (new vertices included).
    pub moved: Vec<u32>,
    /// What refinement appended to the target.
    pub refinement: Refinement,
}

/// Dents `target` (and, with `mutual`, `projectile` by the undented target: Jacobi) as one
/// batch, on the GPU through [`GpuBackend`] with a context (the kernels build the maps and
/// displace, the host refines, fits the falloff, guards against crossings and keeps the volume),
/// else on the CPU (`dent_batch_tracked`), as `dent` and `dent_pair` do.
pub fn dent_pair_or_one(
    context: Option<&GpuContext>,
    target: &mut TriMesh,
    projectile: &mut TriMesh,
    impact: &Impact,
    params: &DentParams,
    mutual: bool,
) -> Result<TargetDent, CliError> {
    let (original_target, original_projectile) = (target.clone(), projectile.clone());
    let mut meshes = vec![original_target.clone()];
    let mut jobs =
        vec![DentJob { target: 0, projectile: &original_projectile, impact: *impact, params: params.clone() }];
    if mutual {
        meshes.push(original_projectile.clone());
        jobs.push(DentJob {
            target: 1,
            projectile: &original_target,
            impact: impact.reversed(),
            params: params.clone(),
        });
    }
    let keys: Vec<usize> = (0..meshes.len()).collect();
    let outcome = match context {
        Some(context) => GpuBackend::new(context).dent_batch(&keys, &mut meshes, &jobs),
        None => dent_batch_tracked(&mut meshes, &jobs),
    };
    let outcome = outcome.map_err(|e| match e.error {
        DentError::Backend(gpu) => CliError::Usage(format!("GPU: {gpu}")),
        error => CliError::Dent(error),
    })?;
    let mut meshes = meshes.into_iter();
    *target = meshes.next().expect("the target is the batch's first mesh");
    if mutual {
        *projectile = meshes.next().expect("the projectile is the batch's second mesh");
    }
    let BatchOutcome { reports, moved, refined } = outcome;
    Ok(TargetDent {
        report: reports.into_iter().next().unwrap_or_default(),
        moved: moved.into_iter().next().unwrap_or_default(),
        refinement: refined.into_iter().next().unwrap_or_default(),
    })
}

fn gpu_error(error: dentbend::gpu::GpuError) -> CliError {
    CliError::Usage(format!("GPU: {error}"))
}
