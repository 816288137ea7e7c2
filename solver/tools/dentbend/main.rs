//! `dentbend`: dent maps and dented meshes from the command line.
//!
//! Exit status: 0 on success, 2 on any error (one `error: …` line on stderr).

mod backend;
mod cmd_demo;
mod cmd_dent;
mod cmd_dentmap;
mod cmd_render;
mod cmd_replay;
mod cmd_run;
mod damage_output;
mod error;
mod file_names;
#[path = "../common/headless.rs"]
mod headless;
mod impacts;
mod logging;
mod options;
mod output;
mod rest_output;
mod run_budget;
mod step_log;
mod vector;

use std::io::Write;
use std::process::ExitCode;

use clap::error::ErrorKind;
use clap::{Parser, Subcommand};

/// Command line of `dentbend`.
#[derive(Debug, Parser)]
#[command(
    name = "dentbend",
    version,
    about = "Dent rigid-body meshes without finite elements (Efficient Denting and Bending of Rigid Bodies, SCA 2014)",
    after_help = "Exit status: 0 on success, 2 on any error. Set RUST_LOG=info for more messages."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The error type of every subcommand.
type CommandResult = Result<(String, Vec<String>), error::CliError>;

#[derive(Debug, Subcommand)]
enum Command {
    /// Computes the dent map a projectile leaves and writes every stage (.npy, .png, .json)
    Dentmap(cmd_dentmap::DentmapArgs),
    /// Dents a target mesh where a projectile hits it and saves the result, with its attributes, as OBJ or glTF
    Dent(cmd_dent::DentArgs),
    /// Draws meshes to a PNG picture
    Render(cmd_render::RenderArgs),
    /// Runs a scene (built-in name or .toml file) with denting in the loop: meshes, PNG frames, summary.json
    Run(cmd_run::RunArgs),
    /// Rebuilds a run's final meshes from its damage.json and the scene's base meshes
    Replay(cmd_replay::ReplayArgs),
    /// Makes the README's pictures and meshes (bunny dent map stages, dented blocks, a pair)
    Demo(cmd_demo::DemoArgs),
}

/// Runs one subcommand; returns its summary line and warnings.
fn execute(command: &Command) -> CommandResult {
    match command {
        Command::Dentmap(args) => cmd_dentmap::run(args).map(|summary| (summary, Vec::new())),
        Command::Dent(args) => cmd_dent::run(args),
        Command::Render(args) => cmd_render::run(args).map(|summary| (summary, Vec::new())),
        Command::Run(args) => cmd_run::run(args).map(|summary| (summary, Vec::new())),
        Command::Replay(args) => cmd_replay::run(args).map(|summary| (summary, Vec::new())),
        Command::Demo(args) => cmd_demo::run(args),
    }
}

/// Exit status for every failure.
const FAILURE: u8 = 2;

fn main() -> ExitCode {
    headless::quiet_headless_vulkan();
    logging::init();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return clap_exit(&e),
    };
    match execute(&cli.command) {
        Ok((summary, warnings)) => {
            warnings.iter().for_each(|w| logging::warn_once(w));
            // A closed stdout (`| head`) is not worth a failure.
            let _ = writeln!(std::io::stdout(), "{summary}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {}", e.one_line());
            ExitCode::from(FAILURE)
        }
    }
}

/// Help and version go out as clap writes them; usage errors become one `error: …` line.
fn clap_exit(e: &clap::Error) -> ExitCode {
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            if e.exit_code() == 0 { ExitCode::SUCCESS } else { ExitCode::from(FAILURE) }
        }
        _ => {
            // The first paragraph is the message; usage and tips follow after a blank line.
            let rendered = e.render().to_string();
            let paragraph = rendered.split("\n\n").next().unwrap_or_default();
            let message = paragraph.split_whitespace().collect::<Vec<_>>().join(" ");
            let message = message.strip_prefix("error:").map_or(message.as_str(), str::trim_start);
            eprintln!("error: {message} (see --help)");
            ExitCode::from(FAILURE)
        }
    }
}
