//! `knitsim`: the command line over the library. Parsing, progress display
//! and error reporting only; every piece of work is a library call.

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use knitsim::app::drape::Progress as DrapeProgress;
use knitsim::app::stability::{run_suite, CaseOutcome, SuiteOptions};
use knitsim::app::{load_fabric, run_drape, run_relax, study, DrapeJob, InputError, RelaxJob, RunStatus};
use knitsim::io::{
    fit_preview, save_json, write_obj, write_png, write_vtk, IoError, ObjOptions, PngOptions, VtkOptions,
};
use knitsim::rod::bending::BendingHessian;
use knitsim::sim::{ContactModeName, ContactParams, RelaxOptions};
use knitsim::solver::linear::{select, AutoParams};
use knitsim::topology::CompileOptions;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

#[derive(Parser)]
#[command(
    name = "knitsim",
    version,
    about = "Knit patterns to yarn-level simulation",
    after_help = EXIT_CODES
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// When compiling a pattern, drop the layout's shape points closer than
    /// this many yarn diameters to a contact (0: keep all). At 1, float
    /// patterns relax several times faster but curl further out of plane
    /// (docs/RELAX.md, "Shape gap").
    #[arg(long, global = true, value_name = "DIAMETERS", default_value_t = 0.0)]
    shape_gap: f64,
}

/// The exit statuses, as `--help` and the README state them.
const EXIT_CODES: &str = "Exit status:
  0    success; for relax: converged
  1    internal or other error; for stability: a case panicked, produced NaN,
       or was called converged on a state its checks reject
  2    bad input: command line, pattern, scene, or a file that cannot be read
       or written
  3    relax: not converged (step cap reached or final state rejected by the
       state checks); drape: not at rest at the end of the scene's duration;
       the state is still written
  130  relax, drape: stopped by Ctrl-C; the state reached is still written";

const EXIT_ERROR: i32 = 1;
const EXIT_BAD_INPUT: i32 = 2;
const EXIT_NOT_CONVERGED: i32 = 3;
const EXIT_STOPPED: i32 = 130;

/// A command-line value the parser accepted but the command cannot use.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
struct BadArgument(String);

#[derive(Subcommand)]
enum Command {
    /// Compile a pattern into yarn-level topology (JSON).
    Compile {
        pattern: PathBuf,
        #[arg(short, long)]
        output: PathBuf,
        /// Print yarns, stitches per kind, loops, contact nodes, floats, rest length.
        #[arg(long)]
        stats: bool,
    },
    /// Write meshes and pictures of a topology or simulation state (or a pattern).
    Export {
        input: PathBuf,
        #[arg(long)]
        vtk: Option<PathBuf>,
        #[arg(long)]
        obj: Option<PathBuf>,
        #[arg(long)]
        png: Option<PathBuf>,
    },
    /// Relax a pattern (or a saved topology/state) to equilibrium.
    Relax {
        input: PathBuf,
        #[arg(short, long)]
        output: PathBuf,
        /// Linear solver for the Newton steps. `auto`: the GPU for problems of
        /// 50K unknowns or more when a hardware adapter exists, else cpu-direct.
        #[arg(long, value_enum, default_value_t = SolverChoice::Auto)]
        solver: SolverChoice,
        /// A scene file (JSON) overriding the embedded default parameters.
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Plain EoL without EIL nodes (to show why EIL matters).
        #[arg(long)]
        no_eil: bool,
        /// Keep every EIL point EIL until the relaxation ends (no
        /// releases between steps; docs/RELAX.md, "Keeping EIL points").
        #[arg(long)]
        keep_eil: bool,
        /// Let yarn slide through its contacts at the Coulomb limit while
        /// relaxing (default: contacts stick; docs/RELAX.md, "Sticking
        /// contacts").
        #[arg(long)]
        sliding: bool,
        /// Stopping tolerance: the largest free force over the force scale
        /// (a loop's bending force kb / l^2, or its weight with gravity on;
        /// docs/RELAX.md, "Stopping test").
        #[arg(long, default_value_t = RelaxOptions::default().tol)]
        tol: f64,
        #[arg(long, default_value_t = RelaxOptions::default().max_steps)]
        max_steps: usize,
        /// Thickness contact between yarns that are not knitted together:
        /// none, penalty, barrier, culled or filtered (overrides the scene's
        /// "contact" mode; default: filtered).
        #[arg(long, value_name = "MODE")]
        contact: Option<ContactModeName>,
        /// The bending stencils' PSD Hessian for Newton: eigen (the nearest
        /// PSD matrix, default) or split (closed form: cheaper iterations, a
        /// deeper relaxation that takes more of them; docs/RELAX.md,
        /// "Bending Hessian"). Overrides the scene's "bending_hessian".
        #[arg(long, value_name = "MODEL")]
        bending_hessian: Option<BendingHessian>,
    },
    /// Drape a pattern (or a saved topology/state): relax it, then simulate
    /// it under gravity on the scene's obstacles until it comes to rest,
    /// writing frames (drape.pvd) as it goes. Without --scene: dropped on a
    /// sphere 0.35 swatch widths in radius, with friction 0.3 and air drag.
    Drape {
        input: PathBuf,
        #[arg(short, long)]
        output: PathBuf,
        /// Linear solver for the Newton steps (as for relax).
        #[arg(long, value_enum, default_value_t = SolverChoice::Auto)]
        solver: SolverChoice,
        /// A scene file (JSON): obstacles, parameters and the "dynamics"
        /// section (gravity, pins, motions, damping, time step, duration,
        /// frame rate; docs/SCENES.md).
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Drape the input as it is, without relaxing it first.
        #[arg(long)]
        no_relax: bool,
    },
    /// Run the numerical stability suite (stiff and extreme cases) and write
    /// stability.md and stability.csv to the output directory.
    Stability {
        #[arg(short, long)]
        output: PathBuf,
        /// A small subset on a 4x4 swatch (for CI).
        #[arg(long)]
        quick: bool,
    },
    /// Error against run time: relax at a ladder of tolerances with each
    /// linear solver, EIL on and off, and compare every result with a
    /// tightly relaxed reference (study.csv, study.md, study.png).
    Study {
        pattern: PathBuf,
        #[arg(short, long)]
        output: PathBuf,
        /// Resize the pattern to N x N stitches.
        #[arg(long, value_name = "N")]
        size: Option<usize>,
        /// The tolerance ladder (comma separated).
        #[arg(long, value_delimiter = ',', default_values_t = study::DEFAULT_TOLS)]
        tols: Vec<f64>,
        /// Step cap of each ladder run.
        #[arg(long, default_value_t = 100)]
        max_steps: usize,
        /// Reference tolerance (default: the smallest of --tols over 10).
        #[arg(long)]
        ref_tol: Option<f64>,
        /// Step cap of the reference run.
        #[arg(long, default_value_t = 400)]
        ref_max_steps: usize,
        /// Linear solvers to compare; one that cannot run here is skipped.
        #[arg(long, value_enum, value_delimiter = ',', default_values_t = [SolverChoice::CpuDirect, SolverChoice::CpuCg, SolverChoice::Gpu])]
        solvers: Vec<SolverChoice>,
        /// EIL settings to compare.
        #[arg(long, value_enum, default_value_t = EilSetting::Both)]
        eil: EilSetting,
        /// A scene file (JSON) overriding the embedded default parameters.
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Appended to the machine description in study.md (e.g. its load).
        #[arg(long)]
        machine_note: Option<String>,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum EilSetting {
    Both,
    On,
    Off,
}

#[derive(Clone, Copy, ValueEnum)]
enum SolverChoice {
    Auto,
    CpuDirect,
    CpuCg,
    /// f32 PCG on the GPU (wgpu); an error if no adapter is found.
    Gpu,
}

impl From<SolverChoice> for knitsim::solver::linear::SolverChoice {
    fn from(c: SolverChoice) -> Self {
        match c {
            SolverChoice::Auto => Self::Auto,
            SolverChoice::CpuDirect => Self::CpuDirect,
            SolverChoice::CpuCg => Self::CpuCg,
            SolverChoice::Gpu => Self::Gpu,
        }
    }
}

fn main() {
    let code = match run(Cli::parse()) {
        Ok(code) => code,
        Err(e) => {
            // A pattern diagnostic comes with its own "error:" heading and snippet.
            if let Some(InputError::Pattern(diagnostic)) = e.downcast_ref::<InputError>() {
                eprintln!("{diagnostic}");
            } else {
                eprintln!("error: {e:#}");
            }
            exit_code(&e)
        }
    };
    std::process::exit(code);
}

/// Bad input (2) when the error's chain names an input, a scene, a file
/// that cannot be read or written, or a refused argument; 1 otherwise.
fn exit_code(e: &anyhow::Error) -> i32 {
    for cause in e.chain() {
        if cause.is::<InputError>()
            || cause.is::<knitsim::scene::SceneError>()
            || cause.is::<BadArgument>()
            || cause.is::<knitsim::sim::dynamics::pins::PinError>()
            || matches!(
                cause.downcast_ref::<knitsim::app::drape::DrapeError>(),
                Some(knitsim::app::drape::DrapeError::Motion { .. } | knitsim::app::drape::DrapeError::Pins(_))
            )
        {
            return EXIT_BAD_INPUT;
        }
        if let Some(io) = cause.downcast_ref::<IoError>() {
            return match io {
                IoError::Export { .. } => EXIT_ERROR,
                _ => EXIT_BAD_INPUT,
            };
        }
        if cause.is::<std::io::Error>() {
            return EXIT_BAD_INPUT;
        }
    }
    EXIT_ERROR
}

fn run(cli: Cli) -> Result<i32> {
    let opts = CompileOptions {
        shape_gap: cli.shape_gap,
        ..CompileOptions::default()
    };
    match cli.command {
        Command::Compile { pattern, output, stats } => compile(&pattern, &opts, &output, stats).map(|()| 0),
        Command::Export { input, vtk, obj, png } => export(&input, &opts, vtk, obj, png).map(|()| 0),
        Command::Stability { output, quick } => stability(&output, quick),
        Command::Drape {
            input,
            output,
            solver,
            scene,
            no_relax,
        } => drape(&input, &output, solver, scene.as_deref(), no_relax, &opts),
        Command::Relax {
            input,
            output,
            solver,
            scene,
            no_eil,
            keep_eil,
            sliding,
            tol,
            max_steps,
            contact,
            bending_hessian,
        } => relax(
            &input,
            &output,
            (solver, scene.as_deref(), no_eil, contact, bending_hessian),
            RelaxOptions {
                tol,
                max_steps,
                keep_eil,
                sliding,
                ..RelaxOptions::default()
            },
            &opts,
        ),
        Command::Study {
            pattern,
            output,
            size,
            tols,
            max_steps,
            ref_tol,
            ref_max_steps,
            solvers,
            eil,
            scene,
            machine_note,
        } => {
            let mut config = study::StudyConfig::new(pattern, output);
            config.size = size;
            config.tols = tols;
            config.max_steps = max_steps;
            config.ref_tol = ref_tol;
            config.ref_max_steps = ref_max_steps;
            config.solvers = solvers.into_iter().map(Into::into).collect();
            config.eil = match eil {
                EilSetting::Both => vec![true, false],
                EilSetting::On => vec![true],
                EilSetting::Off => vec![false],
            };
            config.scene = scene;
            config.compile = opts;
            config.command_line = std::env::args()
                .map(|a| {
                    if a.contains(char::is_whitespace) {
                        format!("'{a}'")
                    } else {
                        a
                    }
                })
                .collect::<Vec<_>>()
                .join(" ");
            if let Some(note) = machine_note {
                config.machine = format!("{}; {note}", config.machine);
            }
            run_study_command(&config).map(|()| 0)
        }
    }
}

fn run_study_command(config: &study::StudyConfig) -> Result<()> {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed)).context("installing the Ctrl-C handler")?;
    let bar = ProgressBar::new(0);
    bar.set_style(
        ProgressStyle::with_template("{spinner} study [{elapsed_precise}] run {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    bar.set_message("relaxing the reference");
    let report = study::run_study(config, Some(&cancel), &mut |done, total, label| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(format!("done: {label}"));
    })?;
    bar.finish_and_clear();
    for s in &report.skipped_solvers {
        println!("skipped {s}");
    }
    if let Some(r) = &report.reference {
        let state = if r.converged { "converged" } else { "NOT converged" };
        println!("reference {state}: residual {:.3e} after {} steps", r.residual, r.steps);
    }
    let stopped = if report.cancelled { " (stopped by user)" } else { "" };
    println!(
        "{} of {} runs{stopped}; outputs in {}",
        report.runs.len(),
        report.planned,
        config.out_dir.display()
    );
    Ok(())
}

fn load(path: &Path, opts: &CompileOptions) -> Result<knitsim::app::Loaded> {
    let loaded = load_fabric(path, opts)?;
    for w in &loaded.warnings {
        eprintln!("{w}");
    }
    Ok(loaded)
}

fn compile(pattern: &Path, opts: &CompileOptions, output: &Path, stats: bool) -> Result<()> {
    let loaded = load(pattern, opts)?;
    save_json(&loaded.fabric, output)?;
    if stats {
        if let Some(p) = &loaded.pattern {
            print!("{}", knitsim::topology::stats(p, &loaded.fabric));
            let g = knitsim::topology::rest_length::predicted_gauge(&loaded.fabric.meta, opts);
            println!(
                "{:<21}  {:>12}\n",
                "predicted gauge",
                format!("{:.1} x {:.1} / 10 cm", g.stitches_per_10cm, g.rows_per_10cm)
            );
        }
    }
    println!("wrote {}", output.display());
    Ok(())
}

fn export(
    input: &Path,
    opts: &CompileOptions,
    vtk: Option<PathBuf>,
    obj: Option<PathBuf>,
    png: Option<PathBuf>,
) -> Result<()> {
    if vtk.is_none() && obj.is_none() && png.is_none() {
        bail!(BadArgument(
            "nothing to export: give at least one of --vtk, --obj, --png".into()
        ));
    }
    let f = load(input, opts)?.fabric;
    if let Some(p) = vtk {
        write_vtk(&f, &p, &VtkOptions::default())?;
        println!("wrote {}", p.display());
    }
    if let Some(p) = obj {
        write_obj(&f, &p, &ObjOptions::default())?;
        println!("wrote {} (+ .mtl)", p.display());
    }
    if let Some(p) = png {
        write_png(&f, &p, &fit_preview(&f, PngOptions::default()))?;
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// The relax command's options, as clap parsed them.
type RelaxFlags<'a> = (
    SolverChoice,
    Option<&'a Path>,
    bool,
    Option<ContactModeName>,
    Option<BendingHessian>,
);

fn relax(
    input: &Path,
    out: &Path,
    (solver, scene, no_eil, contact, bending_hessian): RelaxFlags,
    options: RelaxOptions,
    opts: &CompileOptions,
) -> Result<i32> {
    if !(options.tol > 0.0 && options.tol.is_finite()) {
        bail!(BadArgument(format!(
            "--tol must be a positive number, got {}",
            options.tol
        )));
    }
    let fabric = load(input, opts)?.fabric;
    let mut params = knitsim::scene::params_for(&fabric, scene)?;
    if no_eil {
        params.assign.enable_eil = false;
    }
    if let Some(model) = bending_hessian {
        params.bending_hessian = model;
    }
    if let Some(mode) = contact {
        params.contact = Some(ContactParams {
            mode,
            ..params.contact.unwrap_or_default()
        });
    }
    let n_dofs = knitsim::sim::discretization::dofs::DofLayout::new(&fabric).len();
    let selection = select(solver.into(), n_dofs, &AutoParams::default())?;
    eprintln!("{}", selection.note);
    let solver = selection.solver;
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed)).context("installing the Ctrl-C handler")?;
    let bar = ProgressBar::new(options.max_steps as u64);
    bar.set_style(
        ProgressStyle::with_template("{spinner} relax [{elapsed_precise}] step {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    let contact_on = params.contact_on();
    let job = RelaxJob {
        params,
        options,
        solver,
        out_dir: out.to_path_buf(),
    };
    let outcome = run_relax(fabric, job, Some(&cancel), &mut |k, r| {
        bar.set_position(k as u64);
        bar.set_message(format!("largest force {r:.3e} x scale"));
    })?;
    bar.finish_and_clear();
    let r = &outcome.report;
    println!(
        "{} steps, {} Newton iterations, max EIL {}; outputs in {}",
        r.steps,
        r.newton_iterations,
        r.max_eil,
        out.display()
    );
    println!("{}", r.term_seconds.shares_line(outcome.wall_s));
    if outcome.slid_off_contacts > 0 {
        println!(
            "{} contact(s) removed: a yarn was pulled out of them (scene key remove_slid_off)",
            outcome.slid_off_contacts
        );
    }
    if outcome.separated_contacts > 0 {
        println!(
            "{} contact(s) removed: their yarns pulled apart (scene key separation)",
            outcome.separated_contacts
        );
    }
    if outcome.pending_kind_changes > 0 {
        println!(
            "{} point(s) would change kind (real/EIL) at the next re-assignment: the state is an \
             equilibrium of its own discretization (docs/RELAX.md, \"Stopping test\")",
            outcome.pending_kind_changes
        );
    }
    let c = &outcome.checks;
    let (state, code) = match outcome.status {
        RunStatus::Converged => ("converged".to_string(), 0),
        RunStatus::Stopped => ("stopped by user".to_string(), EXIT_STOPPED),
        RunStatus::NotConverged(why) => {
            println!("not converged: {why}");
            ("NOT converged".to_string(), EXIT_NOT_CONVERGED)
        }
    };
    println!("state checks: {c}");
    if c.overlaps > 0 && outcome.status != RunStatus::Stopped && !contact_on {
        println!(
            "{} segment pair(s) overlap: thickness contact is off, so yarns may pass through each \
             other (--contact filtered keeps them apart)",
            c.overlaps
        );
    }
    println!("{}", outcome.summary.gauge_line());
    println!(
        "largest free force {:.3e} x force scale {:.2e} N ({state}, tol {:.1e}), energy {:.4e} J, wall time {:.2} s",
        r.residual, r.force_scale.value, options.tol, outcome.summary.energy, outcome.wall_s
    );
    Ok(code)
}

fn drape(
    input: &Path,
    out: &Path,
    solver: SolverChoice,
    scene: Option<&Path>,
    no_relax: bool,
    opts: &CompileOptions,
) -> Result<i32> {
    let fabric = load(input, opts)?.fabric;
    let params = knitsim::scene::params_for(&fabric, scene)?;
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed)).context("installing the Ctrl-C handler")?;
    // Without a scene the default one sets the duration once relaxed.
    let duration = match scene {
        Some(_) => params.dynamics.duration,
        None => knitsim::app::drape::scene::DEFAULT_DURATION,
    };
    let duration_ms = (duration * 1e3).round() as u64;
    let bar = ProgressBar::new(duration_ms);
    bar.set_style(
        ProgressStyle::with_template("{spinner} drape [{elapsed_precise}] {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    let job = DrapeJob {
        params,
        default_scene: scene.is_none(),
        relax: (!no_relax).then(RelaxOptions::default),
        solver: solver.into(),
        out_dir: out.to_path_buf(),
    };
    // Without a terminal (a log file) every step is a line instead.
    let log = bar.is_hidden();
    let outcome = run_drape(fabric, job, Some(&cancel), &mut |p| {
        let msg = match p {
            DrapeProgress::Relax(k, r) => format!("relaxing: step {k}, largest force {r:.3e} x scale"),
            DrapeProgress::Drape(row) => format!(
                "t = {:.2} ms of {duration_ms} ms, step {}, dt {:.3} ms, {} Newton, {} retries, speed {:.2e} m/s, kinetic {:.3e} J, {:.1} s",
                row.time * 1e3,
                row.step,
                row.h * 1e3,
                row.newton_iterations,
                row.retries,
                row.max_speed,
                row.kinetic,
                row.wall_s
            ),
        };
        if log {
            eprintln!("{msg}");
        } else {
            bar.set_message(msg);
        }
    })?;
    bar.finish_and_clear();
    eprintln!("{}", outcome.solver_note);
    let s = &outcome.summary;
    if let Some(r) = &outcome.relax {
        println!(
            "relaxed first: {} steps, {} ({:.1} s)",
            r.steps,
            if r.converged { "converged" } else { "NOT converged" },
            s.relax_wall_s
        );
    }
    println!(
        "{} time steps, {} Newton iterations, {:.3e} s simulated; {} frames in {}",
        s.steps,
        s.newton_iterations,
        s.time,
        s.frames,
        out.join("drape.pvd").display()
    );
    println!("{}", s.term_seconds.shares_line(s.wall_s - s.relax_wall_s));
    if s.min_obstacle_clearance.is_finite() {
        println!(
            "closest approach to an obstacle: {:.2} yarn radii (1 = touching)",
            s.min_obstacle_clearance
        );
    }
    println!("state checks: {}", s.checks);
    let [w, h, d] = s.final_size_mm;
    let (state, code) = if s.cancelled {
        ("stopped by user", EXIT_STOPPED)
    } else if s.at_rest {
        ("at rest", 0)
    } else {
        ("NOT at rest at the end of the duration", EXIT_NOT_CONVERGED)
    };
    println!(
        "final size {w:.1} x {h:.1} x {d:.1} mm, largest speed {:.2e} m/s ({state}), wall time {:.2} s",
        s.final_max_speed, s.wall_s
    );
    Ok(code)
}

fn stability(out: &Path, quick: bool) -> Result<i32> {
    let opts = SuiteOptions { quick };
    eprintln!("{} cases; outputs in {}", opts.cases().len(), out.display());
    let rows = run_suite(out, opts, &mut |r| {
        eprintln!(
            "{:<32} {:<14} {:>3} steps {:>4} Newton  residual {:.2e}  NaN {}  overlaps {}  strain {:.2}%  {:.1} s  {}",
            r.name,
            r.outcome.label(),
            r.steps,
            r.newton_iterations,
            r.residual,
            r.checks.non_finite,
            r.checks.overlaps,
            100.0 * r.checks.max_strain,
            r.wall_s,
            r.outcome.detail()
        )
    })?;
    println!(
        "wrote {} and {}",
        out.join("stability.md").display(),
        out.join("stability.csv").display()
    );
    let bad = rows.iter().filter(|r| {
        matches!(r.outcome, CaseOutcome::Panic(_))
            || r.checks.non_finite > 0
            || (r.outcome == CaseOutcome::Converged && !r.checks_pass())
    });
    Ok(if bad.count() > 0 { EXIT_ERROR } else { 0 })
}
