//! The plug-in's tests, one file a module, in one test binary: Bevy, wgpu and the physics
//! engines are linked once rather than once a file. Apps with a renderer run one at a time,
//! so every trial does (`cargo test -p bevy_dentbend -- gpu_path::` runs one file's).

mod common;

#[cfg(feature = "avian")]
mod avian;
mod bend;
mod fracture;
mod game_assets;
mod gpu_path;
mod hostile;
mod rapier_rain;
mod save_restore;
mod scaled;
mod schedules;
mod split_entities;

use std::process::ExitCode;

use libtest_mimic::Arguments;

fn main() -> ExitCode {
    let mut args = Arguments::from_args();
    args.test_threads = Some(1);
    let mut trials: Vec<_> = [
        bend::tests(),
        fracture::tests(),
        game_assets::tests(),
        gpu_path::tests(),
        hostile::tests(),
        rapier_rain::tests(),
        save_restore::tests(),
        scaled::tests(),
        schedules::tests(),
        split_entities::tests(),
    ]
    .into_iter()
    .flatten()
    .collect();
    #[cfg(feature = "avian")]
    trials.extend(avian::tests());
    libtest_mimic::run(&args, trials).exit_code()
}
