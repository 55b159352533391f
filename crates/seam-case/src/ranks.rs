//! Runs over MPI ranks (cargo feature `mpi`): `mpirun -np N seam assemble …`
//! assembles the operator over the ranks, by the library's parts
//! ([`seam::parts`]); the binary drives this protocol, and any other program
//! linking seam-case can.
//!
//! Rank 0 reads both surfaces, splits the slave faces by recursive coordinate
//! bisection, and sends each rank its faces and the master faces of its
//! region (a rendezvous by boxes); every rank assembles its faces' blocks
//! (rank 0 too) and sends them back; rank 0 sums the rows in face order and
//! writes the files: the same bytes as one process. `seam solve --solver
//! petsc` runs its PETSc systems over the ranks (rank 0 leads, the others
//! follow), its interfaces' operators as `assemble` does
//! ([`operators_over_ranks`], [`Ranks::follow`]) and, for glued bodies, the
//! stiffness of each rank's cells on that rank ([`seam_fem::partition`]);
//! any other command under N > 1 ranks is refused.
//!
//! Messages are byte arrays (a u64 length, then chunks of at most 1 GiB, so
//! MPI's 32-bit counts are never exceeded). A rank whose part cannot be had
//! (rank 0 failed before sending, or the bytes are not a part) gets or sends
//! an empty message, and every rank exits: rank 0 with its one-line error and
//! code 2, the others silently with code 2.

use crate::assemble::{Assembler, AssemblerError, Progress, RankReport};
use crate::Failure;
use mpi::topology::{Communicator, SimpleCommunicator};
use mpi::traits::{Destination, Source};
use seam::parts::{assemble_here, assemble_parts, split, PartBlocks, PartJob};
use seam::{FaceTree, Mortar, MortarError, MortarOptions, SurfaceMesh};
use std::cell::Cell;
use std::time::Instant;

/// A rank other than 0 could not do its share: rank 0 failed first (and
/// says why), or the part it sent could not be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("this MPI rank could not do its share of the run (rank 0 says why)")]
pub struct Abandoned;

/// The largest message MPI is handed at once.
const CHUNK: usize = 1 << 30;

/// MPI for the whole run (finalised when dropped, at the end of `main`).
pub struct Ranks {
    _universe: mpi::environment::Universe,
    world: SimpleCommunicator,
}

/// Whether an MPI launcher started this process (`mpirun`, `mpiexec`, `srun`:
/// Open MPI's, PMI's or PMIx's variables are set). Without one seam is one
/// process and does not start MPI, whose singleton start-up costs about a
/// tenth of a second per command.
pub fn launched() -> bool {
    ["OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"]
        .iter()
        .any(|v| std::env::var_os(v).is_some())
}

impl Ranks {
    /// Initialises MPI (a singleton without `mpirun`), from the main thread.
    /// Calls to MPI come from one thread at a time ("serialized"): the
    /// operator's from the main thread, PETSc's from whichever thread of the
    /// solve holds PETSc's lock.
    ///
    /// # Errors
    /// MPI was initialised before in this process.
    pub fn initialize() -> Result<Ranks, Failure> {
        let (universe, _) = mpi::initialize_with_threading(mpi::Threading::Serialized)
            .ok_or_else(|| Failure::Error("MPI was initialised twice".into()))?;
        let world = universe.world();
        Ok(Ranks { _universe: universe, world })
    }

    /// Number of ranks.
    pub fn size(&self) -> usize {
        self.world.size() as usize
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.world.rank() as usize
    }

    /// A rank other than 0 of `mpirun -np N seam solve`: follows rank 0's
    /// PETSc calls, and assembles its part of each interface's operator when
    /// rank 0 yields for it ([`operators_over_ranks`]) and the stiffness of
    /// the cells rank 0 sends it ([`seam_fem::partition::answer`]), until
    /// rank 0 ends. `Err` when a PETSc call failed here (rank 0 has failed too).
    pub fn follow(&self) -> Result<(), Abandoned> {
        loop {
            match seam_fem::petsc::follow_petsc() {
                Ok(seam_fem::petsc::Followed::Released) => return Ok(()),
                Ok(seam_fem::petsc::Followed::Yielded) => {
                    // A part that cannot be had: rank 0 knows it and fails.
                    let _ = self.work();
                }
                Ok(seam_fem::petsc::Followed::Job(cells)) => seam_fem::partition::answer(&cells),
                Err(_) => return Err(Abandoned),
            }
        }
    }

    /// Rank 0's assembler: parts to the other ranks, blocks back.
    pub fn assembler(&self) -> OverRanks<'_> {
        OverRanks { world: &self.world, sent: Cell::new(false) }
    }

    /// A rank other than 0: waits for its part, assembles it on rayon's
    /// global pool and sends the blocks back. `Err` when there was no part
    /// (rank 0 failed) or it could not be read.
    pub fn work(&self) -> Result<(), Abandoned> {
        let root = self.world.process_at_rank(0);
        let bytes = receive(&root);
        let job = match bytes.is_empty() {
            true => return Err(Abandoned),
            false => PartJob::from_bytes(&bytes),
        };
        let Ok(job) = job else {
            send(&root, &[]);
            root.send(&[0.0f64, f64::NAN][..]);
            return Err(Abandoned);
        };
        let start = Instant::now();
        let blocks = job.assemble().to_bytes();
        let seconds = start.elapsed().as_secs_f64(); // not the wait for rank 0 to receive
        let peak = crate::process::peak_memory_mb().unwrap_or(f64::NAN);
        send(&root, &blocks);
        root.send(&[seconds, peak][..]);
        Ok(())
    }
}

/// Rank 0 of `mpirun -np N seam solve`: how every interface's operator is
/// assembled over the ranks ([`OverRanks`], the same B and D bit for bit),
/// the other ranks handed over by PETSc's followers for it
/// ([`Ranks::follow`]). For [`crate::solve::SolveOptions::operators`]; MPI
/// must be initialised ([`Ranks::initialize`]) for as long as solves use it.
pub fn operators_over_ranks() -> seam_fem::Operators {
    let over_ranks = |master: &SurfaceMesh, slave: &SurfaceMesh, options: &MortarOptions| {
        seam_fem::petsc::yield_petsc();
        // MPI is initialised for the whole run (`main`); this thread is the
        // only one calling it now (interfaces are assembled one at a time).
        let world = SimpleCommunicator::world();
        let assembler = OverRanks { world: &world, sent: Cell::new(false) };
        let tree = FaceTree::new(master);
        assembler.assemble(master, &tree, slave, options, &()).map(|(mortar, _)| mortar).map_err(
            |e| match e {
                AssemblerError::Mortar(e) => e,
                AssemblerError::Process(message) => MortarError::InvalidOption(message),
            },
        )
    };
    // One closure for the whole process (a few bytes), referred to by solves.
    seam_fem::Operators::By(Box::leak(Box::new(over_ranks)))
}

/// Rank 0's side of [`Ranks::work`] ([`Assembler`]).
pub struct OverRanks<'a> {
    world: &'a SimpleCommunicator,
    /// Whether the other ranks have had their parts.
    sent: Cell<bool>,
}

impl OverRanks<'_> {
    /// Tells ranks still waiting for a part that there is none (rank 0
    /// failed before assembling).
    pub fn release(&self) {
        if !self.sent.replace(true) {
            for r in 1..self.world.size() {
                send(&self.world.process_at_rank(r), &[]);
            }
        }
    }
}

impl Assembler for OverRanks<'_> {
    fn assemble(
        &self,
        master: &SurfaceMesh,
        tree: &FaceTree,
        slave: &SurfaceMesh,
        options: &MortarOptions,
        progress: &dyn Progress,
    ) -> Result<(Mortar, Option<Vec<RankReport>>), AssemblerError> {
        let size = self.world.size() as usize;
        let parts = split(tree, slave, options, size);
        let mut reports = vec![RankReport::default(); size];
        for (r, part) in parts.iter().enumerate().skip(1) {
            let job = PartJob::new(master, slave, options, part);
            let bytes = job.to_bytes();
            send(&self.world.process_at_rank(r as i32), &bytes);
            reports[r].bytes_received = bytes.len() as u64;
        }
        self.sent.set(true);
        for (r, part) in parts.iter().enumerate() {
            (reports[r].slave_faces, reports[r].ghost_master_faces) =
                (part.slave_faces.len(), part.master_faces.len());
        }
        let start = Instant::now();
        let own = assemble_here(master, tree, slave, options, &parts[0]);
        progress.advance(own.len());
        reports[0].seconds = start.elapsed().as_secs_f64();
        // Every rank's answer is received (blocks, then seconds) before any is
        // judged, so that no rank is left waiting to hand its blocks over.
        let mut blocks = vec![Ok(own)];
        for (r, report) in reports.iter_mut().enumerate().skip(1) {
            let process = self.world.process_at_rank(r as i32);
            let bytes = receive(&process);
            let mut figures = [0.0f64; 2];
            process.receive_into(&mut figures[..]);
            report.seconds = figures[0];
            report.peak_memory_mb = Some(figures[1]).filter(|m| m.is_finite());
            report.bytes_sent = bytes.len() as u64;
            let part = PartBlocks::from_bytes(&bytes).map_err(|_| {
                AssemblerError::Process(format!("MPI rank {r} could not assemble its part of the interface"))
            });
            progress.advance(part.as_ref().map_or(0, PartBlocks::len));
            blocks.push(part);
        }
        let blocks = blocks.into_iter().collect::<Result<Vec<_>, _>>()?;
        Ok((assemble_parts(master, tree, slave, options, blocks)?, Some(reports)))
    }
}

fn send(to: &impl Destination, bytes: &[u8]) {
    to.send(&(bytes.len() as u64));
    for chunk in bytes.chunks(CHUNK) {
        to.send(chunk);
    }
}

/// Receives a byte array. Waits by probing every 0.2 ms, not in MPI's
/// blocking receive, which spins: a rank waiting for its part or for the
/// others' blocks must leave the cores to the ranks still computing.
fn receive(from: &impl Source) -> Vec<u8> {
    while from.immediate_probe().is_none() {
        std::thread::sleep(std::time::Duration::from_micros(200));
    }
    let (len, _) = from.receive::<u64>();
    let mut bytes = vec![0u8; len as usize];
    for chunk in bytes.chunks_mut(CHUNK) {
        from.receive_into(chunk);
    }
    bytes
}
