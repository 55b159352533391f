/*
 * The C side of seam's PETSc layer: PETSc's API is macro-heavy (communicators,
 * error checking), so the few things seam needs are written here once, in C,
 * against PETSc's own headers, and called from Rust (src/lib.rs). Every PETSc
 * call is checked; an error returns its code and a one-line message in the
 * caller's buffer (PETSc's return-error handler is pushed at initialisation,
 * so nothing is printed).
 *
 * Systems live on PETSC_COMM_WORLD. One process: sequential matrices, as
 * before. Under mpirun with N > 1 ranks, rank 0 *leads* (it runs seam's
 * pipeline and calls the functions below as one process would) and the other
 * ranks *follow* (seam_petsc_follow): every call of the leader is first
 * broadcast as a command, with the rows each rank owns (contiguous blocks of
 * whole points, balanced by entries) sent to it, then all ranks make the same
 * collective PETSc calls on their rows (MPIAIJ, distributed vectors,
 * near-nullspace and field splits); a solution's pieces are gathered on the
 * leader. Every command ends with all ranks agreeing on success (an
 * MPI_Allreduce of the error code), so that no rank goes on alone. Between
 * commands the leader may send each follower a job (bytes of the program's
 * own), which the follower's caller does and answers; a system can be
 * formed from the matrix entries each rank staged
 * (seam_petsc_system_create_staged), so that its matrix is never whole on
 * one rank.
 */
#include <petscksp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef __GLIBC__
#include <malloc.h>

/* Debian's libsuperlu_dist, which PETSc links, switches glibc's mmap and
 * heap trimming off in its constructor (mallopt(M_MMAP_MAX, 0) and
 * mallopt(M_TRIM_THRESHOLD, -1)): a process that links PETSc would then keep
 * every byte it ever freed, and a solve's peak memory would be the sum of its
 * phases' (K, the reduction, PETSc's copy) rather than their largest
 * (measured: 3.49 GB against 2.98 GB at 433k unknowns, glue_bench --row 16
 * dual-petsc). This constructor runs after the shared libraries' ones and
 * sets what glibc's dynamic thresholds settle at in a process that frees large
 * blocks: blocks of 32 MiB or more are mapped, and unmapped at free; a free
 * heap top beyond 64 MiB is given back. */
__attribute__((constructor)) static void seam_petsc_restore_malloc(void) {
  mallopt(M_MMAP_MAX, 65536);
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 64 * 1024 * 1024);
}
#endif

/* What a solve reports. */
typedef struct {
  PetscInt iterations;
  PetscReal ksp_residual;  /* the norm KSP's convergence test used */
  PetscReal true_residual; /* ‖b − A x‖₂ / ‖b‖₂ */
  int reason;             /* KSPConvergedReason: > 0 converged, < 0 diverged */
  char reason_name[64];
  char ksp_type[64];
  char pc_type[64];
  double assembly_seconds; /* building the PETSc matrix */
  double setup_seconds;    /* KSPSetUp: the preconditioner (GAMG's hierarchy) */
  double solve_seconds;    /* KSPSolve */
  int ranks;               /* the processes the system is distributed over */
} seam_petsc_report;

/* A matrix with its KSP, the preconditioner set up at the first solve (so
 * that the caller can free its copy of the matrix first), solved with any
 * number of right-hand sides. On rank r it holds rows [rstart, rstart + m)
 * of n; the leader also keeps every rank's first row (ranges, size + 1). */
typedef struct {
  Mat A;
  Mat op; /* the operator when it is not A (seam_petsc_system_set_operator), else NULL */
  KSP ksp;
  PetscInt n, bs, rstart, m;
  PetscInt *ranges;
  int id;
  double rtol; /* the KSP's relative tolerance after the options */
  double assembly_seconds, setup_seconds;
} seam_petsc_system;

/* What the leader broadcasts before each call (all ranks run one binary:
 * the layout is the same everywhere). */
enum { CMD_INIT = 1, CMD_CREATE, CMD_SOLVE, CMD_DESTROY, CMD_EXIT, CMD_YIELD, CMD_JOB, CMD_STAGED, CMD_OPERATOR };
typedef struct {
  int cmd, id;
  PetscInt n, n_first, bs, n_modes, max_it;
  int symmetric; /* CMD_CREATE, CMD_STAGED: the matrix is symmetric; CMD_OPERATOR: refresh */
  int nonzero_guess, argc;
  long long bytes; /* CMD_INIT: the options that follow */
  double rtol;
  char ksp_type[64], pc_type[64];
} command;

/* This process leads ranks that follow (rank 0 under mpirun, N > 1). */
static int leading = 0;
/* This process follows rank 0 (seam_petsc_follow). */
static int following = 0;
/* The followers have been told to exit. */
static int released = 0;
/* The leader's next system id. */
static int next_id = 0;

/* The MPI message tag of the leader's data. */
#define TAG 7301
/* The most elements handed to MPI at once (its counts are ints). */
#define CHUNK ((size_t)1 << 27)

static void message(PetscErrorCode code, char *err, size_t len)
{
  const char *text = NULL;
  char       *specific = NULL;
  if (!err || !len) return;
  PetscErrorMessage(code, &text, &specific);
  const char *m = (specific && *specific) ? specific : (text ? text : "unknown PETSc error");
  snprintf(err, len, "%s", m);
  /* One line: PETSc's messages may end in or contain newlines. */
  for (char *c = err; *c; c++)
    if (*c == '\n' || *c == '\r') *c = ' ';
  size_t l = strlen(err);
  while (l && err[l - 1] == ' ') err[--l] = '\0';
}

#define TRY(call) \
  do { \
    PetscErrorCode ierr_ = (call); \
    if (ierr_) { \
      message(ierr_, err, errlen); \
      code = ierr_; \
      goto fail; \
    } \
  } while (0)

static int world_size(void)
{
  int initialized = 0, size = 1;
  (void)MPI_Initialized(&initialized);
  if (initialized) MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

static int world_rank(void)
{
  int initialized = 0, rank = 0;
  (void)MPI_Initialized(&initialized);
  if (initialized) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

/* Whether calls are distributed: this process leads other ranks. */
static int distributed(void)
{
  return leading && world_size() > 1;
}

static void send_array(const void *data, size_t count, MPI_Datatype type, size_t size, int to)
{
  const char *p = (const char *)data;
  for (size_t done = 0; done < count; done += CHUNK) {
    size_t k = count - done < CHUNK ? count - done : CHUNK;
    (void)MPI_Send(p + done * size, (int)k, type, to, TAG, MPI_COMM_WORLD);
  }
}

static void receive_array(void *data, size_t count, MPI_Datatype type, size_t size, int from)
{
  char *p = (char *)data;
  for (size_t done = 0; done < count; done += CHUNK) {
    size_t k = count - done < CHUNK ? count - done : CHUNK;
    (void)MPI_Recv(p + done * size, (int)k, type, from, TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  }
}

/* The leader's command to every rank (a non-blocking broadcast, which the
 * followers wait for without spinning: see seam_petsc_follow). */
static void broadcast(command *c)
{
  MPI_Request request;
  (void)MPI_Ibcast(c, (int)sizeof(*c), MPI_BYTE, 0, MPI_COMM_WORLD, &request);
  (void)MPI_Wait(&request, MPI_STATUS_IGNORE);
}

/* Whether every rank succeeded (code 0 here and everywhere; only here
 * when this process neither leads nor follows). */
static int agreed(int code)
{
  int failed = code != 0, any = failed;
  if ((leading || following) && world_size() > 1)
    (void)MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return !any;
}

static void finalize_at_exit(void)
{
  PetscBool initialized = PETSC_FALSE, finalized = PETSC_FALSE;
  PetscInitialized(&initialized);
  PetscFinalized(&finalized);
  if (initialized && !finalized) PetscFinalize();
}

/* The leader tells the followers to leave seam_petsc_follow (once). */
static void release(void)
{
  if (distributed() && !released) {
    command c;
    memset(&c, 0, sizeof(c));
    c.cmd = CMD_EXIT;
    broadcast(&c);
    released = 1;
  }
}

/* Finalises PETSc now if it was initialised (before the caller finalises an
 * MPI it initialised itself); the leader first releases its followers, which
 * then finalise too. The exit handler then does nothing. */
void seam_petsc_finalize(void)
{
  release();
  finalize_at_exit();
}

/* Makes this process the leader of the other ranks (which must call
 * seam_petsc_follow); returns the number of ranks. */
int seam_petsc_lead(void)
{
  leading = world_rank() == 0;
  return world_size();
}

static double now(void)
{
  PetscLogDouble t = 0;
  PetscTime(&t);
  return (double)t;
}

/* PETSc's initialisation on this process with argv (argc words), or the
 * options `more` added to the database when it is initialised. */
static int initialize_here(int argc, char **argv, const char *more, char *err, size_t errlen)
{
  PetscErrorCode code = 0;
  PetscBool      initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized) {
    code = PetscInitialize(&argc, &argv, NULL, NULL);
    if (code) {
      snprintf(err, errlen, "PetscInitialize failed with error code %d", (int)code);
      return (int)code;
    }
    PetscPushErrorHandler(PetscReturnErrorHandler, NULL);
    atexit(finalize_at_exit);
  }
  if (more && *more) TRY(PetscOptionsInsertString(NULL, more));
  return 0;
fail:
  return (int)code;
}

/* Initialises PETSc (and MPI, unless the caller did) once per process with
 * the options in argv (after PETSC_OPTIONS, which PETSc reads itself);
 * PetscFinalize runs at process exit (so that -log_view prints). Later calls
 * insert `more` into the database. The leader's followers do the same.
 * Returns 0 or an error code; *world_size is the number of ranks. */
int seam_petsc_initialize(int argc, char **argv, const char *more, int *world, char *err, size_t errlen)
{
  int code;
  *world = world_size();
  if (distributed()) {
    /* argv's words then `more`, each NUL-terminated, after the command. */
    command c;
    size_t  bytes = more ? strlen(more) + 1 : 1;
    memset(&c, 0, sizeof(c));
    for (int k = 0; k < argc; k++) bytes += strlen(argv[k]) + 1;
    char *packed = (char *)calloc(bytes, 1), *p = packed;
    if (!packed) {
      snprintf(err, errlen, "out of memory");
      return PETSC_ERR_MEM;
    }
    for (int k = 0; k < argc; k++) p = stpcpy(p, argv[k]) + 1;
    if (more) strcpy(p, more);
    c.cmd   = CMD_INIT;
    c.argc  = argc;
    c.bytes = (long long)bytes;
    broadcast(&c);
    (void)MPI_Bcast(packed, (int)bytes, MPI_BYTE, 0, MPI_COMM_WORLD);
    free(packed);
  }
  code = initialize_here(argc, argv, more, err, errlen);
  if (!agreed(code) && !code) {
    snprintf(err, errlen, "PETSc failed to start on another MPI rank");
    code = PETSC_ERR_LIB;
  }
  return code;
}

/* sizeof(PetscInt), for the Rust side to check its index type. */
int seam_petsc_petscint_size(void)
{
  return (int)sizeof(PetscInt);
}

/* Rows [rstart, rstart + m) of the n × n matrix (local CSR, 0-based, global
 * sorted columns) as AIJ, or what -mat_type chooses (from_options), with
 * block size bs; the columns of the same range are this rank's diagonal
 * block. */
static PetscErrorCode build_matrix(PetscInt n, PetscInt rstart, PetscInt m, PetscInt bs, const PetscInt *rowptr,
                                   const PetscInt *cols, const PetscScalar *vals, int symmetric, int from_options,
                                   Mat *out)
{
  Mat       A;
  PetscInt *nnz, *onnz, *bnnz, *bonnz, *mark;
  PetscInt  nb = m / bs + 1, rend = rstart + m;
  PetscBool sbaij = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(MatCreate(PETSC_COMM_WORLD, &A));
  PetscCall(MatSetSizes(A, m, m, n, n));
  PetscCall(MatSetType(A, MATAIJ));
  PetscCall(MatSetBlockSize(A, bs));
  if (from_options) PetscCall(MatSetFromOptions(A));
  /* Preallocation for AIJ (entries per row, in the diagonal block and off
   * it) and BAIJ/SBAIJ (blocks per block row); only the calls of the
   * matrix's type take effect. */
  PetscCall(PetscCalloc1(m + 1, &nnz));
  PetscCall(PetscCalloc1(m + 1, &onnz));
  PetscCall(PetscCalloc1(nb, &bnnz));
  PetscCall(PetscCalloc1(nb, &bonnz));
  PetscCall(PetscMalloc1(n / bs + 1, &mark));
  for (PetscInt r = 0; r <= n / bs; r++) mark[r] = -1;
  for (PetscInt i = 0; i < m; i++) {
    for (PetscInt j = rowptr[i]; j < rowptr[i + 1]; j++) {
      PetscInt  col = cols[j], block = col / bs;
      PetscBool diagonal = col >= rstart && col < rend;
      if (diagonal) nnz[i]++;
      else onnz[i]++;
      if (mark[block] != i / bs) {
        mark[block] = i / bs;
        if (diagonal) bnnz[i / bs]++;
        else bonnz[i / bs]++;
      }
    }
  }
  PetscCall(MatSeqAIJSetPreallocation(A, 0, nnz));
  PetscCall(MatMPIAIJSetPreallocation(A, 0, nnz, 0, onnz));
  PetscCall(MatSeqBAIJSetPreallocation(A, bs, 0, bnnz));
  PetscCall(MatMPIBAIJSetPreallocation(A, bs, 0, bnnz, 0, bonnz));
  PetscCall(MatSeqSBAIJSetPreallocation(A, bs, 0, bnnz));
  PetscCall(MatMPISBAIJSetPreallocation(A, bs, 0, bnnz, 0, bonnz));
  PetscCall(PetscFree(nnz));
  PetscCall(PetscFree(onnz));
  PetscCall(PetscFree(bnnz));
  PetscCall(PetscFree(bonnz));
  PetscCall(PetscFree(mark));
  PetscCall(MatSetOption(A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)A, &sbaij, MATSEQSBAIJ, MATMPISBAIJ, MATSBAIJ, ""));
  if (sbaij) PetscCall(MatSetOption(A, MAT_IGNORE_LOWER_TRIANGULAR, PETSC_TRUE));
  for (PetscInt i = 0; i < m; i++) {
    PetscInt row = rstart + i;
    PetscCall(MatSetValues(A, 1, &row, rowptr[i + 1] - rowptr[i], cols + rowptr[i], vals + rowptr[i], INSERT_VALUES));
  }
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  if (symmetric) PetscCall(MatSetOption(A, MAT_SYMMETRIC, PETSC_TRUE));
  *out = A;
  PetscFunctionReturn(0);
}

/* The rows of each rank: contiguous, balanced by entries, split between
 * points (multiples of bs) below n_first. */
static void partition_rows(PetscInt n, PetscInt n_first, PetscInt bs, const PetscInt *rowptr, int size, PetscInt *ranges)
{
  ranges[0]    = 0;
  ranges[size] = n;
  for (int r = 1; r < size; r++) {
    double   target = (double)rowptr[n] * r / size;
    PetscInt lo = ranges[r - 1], hi = n;
    while (lo < hi) { /* the first row whose entries before it reach the target */
      PetscInt mid = lo + (hi - lo) / 2;
      if ((double)rowptr[mid] < target) lo = mid + 1;
      else hi = mid;
    }
    if (lo < n_first) lo -= lo % bs;
    ranges[r] = lo < ranges[r - 1] ? ranges[r - 1] : lo;
  }
}

/* The part of the first field [0, n_first) in rows [rstart, rstart + m). */
static PetscInt first_part(PetscInt n_first, PetscInt rstart, PetscInt m)
{
  PetscInt end = rstart + m < n_first ? rstart + m : n_first;
  return end > rstart ? end - rstart : 0;
}

/* Every rank: the system of the command on this rank's rows [rstart,
 * rstart + m) of the matrix A (taken over: destroyed on failure), assembled
 * for `assembly` seconds before, with its part of the near-nullspace vectors
 * (the first-field rows of each, `stride` apart) and its KSP. */
static int configure_here(const command *c, PetscInt rstart, PetscInt m, Mat A, double assembly,
                          const PetscScalar *modes, size_t stride, seam_petsc_system **out, char *err, size_t errlen)
{
  PetscErrorCode      code = 0;
  seam_petsc_system  *s = NULL;
  Vec                 near[16] = {NULL};
  MatNullSpace        nullspace = NULL;
  IS                  fields[2] = {NULL, NULL};
  PC                  pc;
  /* A saddle point [A Bᵀ; B 0] when the first field ends before n: the
   * matrix without blocks, the first field (block size bs) split from the
   * second by PCFIELDSPLIT, the near-nullspace on the first field. */
  const PetscInt      n = c->n, n_first = c->n_first, bs = c->bs;
  const PetscBool     split = n_first < n;
  const PetscInt      mat_bs = split ? 1 : bs;
  const PetscInt      m_first = first_part(n_first, rstart, m);
  double              t0;

  *out = NULL;
  s = (seam_petsc_system *)calloc(1, sizeof(*s));
  if (!s) {
    MatDestroy(&A);
    snprintf(err, errlen, "out of memory");
    return PETSC_ERR_MEM;
  }
  s->A = A;
  s->n      = n;
  s->bs     = mat_bs;
  s->rstart = rstart;
  s->m      = m;
  s->id     = c->id;
  t0        = now() - assembly;
  if (c->n_modes > 16) {
    snprintf(err, errlen, "at most 16 near-nullspace vectors, got %d", (int)c->n_modes);
    code = PETSC_ERR_ARG_OUTOFRANGE;
    goto fail;
  }
  for (PetscInt k = 0; k < c->n_modes; k++) {
    PetscScalar *a;
    TRY(VecCreateMPI(PETSC_COMM_WORLD, m_first, n_first, &near[k]));
    TRY(VecSetBlockSize(near[k], bs));
    TRY(VecGetArray(near[k], &a));
    if (m_first) memcpy(a, modes + (size_t)k * stride, (size_t)m_first * sizeof(PetscScalar));
    TRY(VecRestoreArray(near[k], &a));
  }
  if (c->n_modes > 0) TRY(MatNullSpaceCreate(PETSC_COMM_WORLD, PETSC_FALSE, c->n_modes, near, &nullspace));
  if (nullspace && !split) TRY(MatSetNearNullSpace(s->A, nullspace));
  s->assembly_seconds = now() - t0;
  t0 = now();
  TRY(KSPCreate(PETSC_COMM_WORLD, &s->ksp));
  TRY(KSPSetOperators(s->ksp, s->A, s->A));
  TRY(KSPSetType(s->ksp, c->ksp_type));
  TRY(KSPGetPC(s->ksp, &pc));
  TRY(PCSetType(pc, c->pc_type));
  if (split) {
    PetscBool fieldsplit = PETSC_FALSE;
    TRY(ISCreateStride(PETSC_COMM_WORLD, m_first, rstart, 1, &fields[0]));
    TRY(ISSetBlockSize(fields[0], bs));
    TRY(ISCreateStride(PETSC_COMM_WORLD, m - m_first, rstart + m_first, 1, &fields[1]));
    if (nullspace) TRY(PetscObjectCompose((PetscObject)fields[0], "nearnullspace", (PetscObject)nullspace));
    TRY(PetscObjectTypeCompare((PetscObject)pc, PCFIELDSPLIT, &fieldsplit));
    if (fieldsplit) {
      TRY(PCFieldSplitSetIS(pc, "0", fields[0]));
      TRY(PCFieldSplitSetIS(pc, "1", fields[1]));
      TRY(PCFieldSplitSetType(pc, PC_COMPOSITE_SCHUR));
      /* Upper triangular: one cycle on the displacements per application,
       * not full's two, at about the same FGMRES iterations
       * (BENCHMARKS.md, "Finite deformation"). */
      TRY(PCFieldSplitSetSchurFactType(pc, PC_FIELDSPLIT_SCHUR_FACT_UPPER));
      TRY(PCFieldSplitSetSchurPre(pc, PC_FIELDSPLIT_SCHUR_PRE_SELFP, NULL));
      /* The blocks' defaults, unless the options database sets them: one
       * multigrid cycle on the displacements, Jacobi on the Schur
       * complement's approximation B diag(A)⁻¹ Bᵀ. */
      const char *defaults[][2] = {{"-fieldsplit_0_ksp_type", "preonly"},
                                   {"-fieldsplit_0_pc_type", "gamg"},
                                   {"-fieldsplit_1_ksp_type", "preonly"},
                                   {"-fieldsplit_1_pc_type", "jacobi"}};
      for (size_t k = 0; k < sizeof(defaults) / sizeof(defaults[0]); k++) {
        PetscBool set = PETSC_FALSE;
        TRY(PetscOptionsHasName(NULL, NULL, defaults[k][0], &set));
        if (!set) TRY(PetscOptionsSetValue(NULL, defaults[k][0], defaults[k][1]));
      }
    }
  }
  {
    /* One process: GAMG's Galerkin products PᵀAP by the triple product of
     * Pᵀ, A and P ("rap") unless the options say otherwise: 1.7× faster
     * setups than the default on the dual-reduced glue systems, whose
     * interface rows are dense (BENCHMARKS.md). */
    PetscBool seqaij = PETSC_FALSE, set = PETSC_FALSE;
    TRY(PetscObjectTypeCompare((PetscObject)s->A, MATSEQAIJ, &seqaij));
    TRY(PetscOptionsHasName(NULL, NULL, "-matptap_via", &set));
    if (seqaij && !set) TRY(PetscOptionsSetValue(NULL, "-matptap_via", "rap"));
  }
  /* A refreshed matrix (operator_here) keeps GAMG's interpolation; a no-op
   * for other PC types, -pc_gamg_reuse_interpolation false undoes it. */
  TRY(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE));
  TRY(KSPSetTolerances(s->ksp, c->rtol, PETSC_DEFAULT, PETSC_DEFAULT, c->max_it));
  /* (F)GMRES restarts after 100 iterations, not 30 (unless -ksp_gmres_restart
   * says otherwise): a frictional Newton step with GAMG needs some 90 to
   * reach 1e-12, and restarting at 30 made it 750 (BENCHMARKS.md). A no-op
   * for other KSP types. */
  TRY(KSPGMRESSetRestart(s->ksp, 100));
  TRY(KSPSetFromOptions(s->ksp));
  TRY(KSPGetTolerances(s->ksp, &s->rtol, NULL, NULL, NULL));
  s->setup_seconds = now() - t0; /* KSPSetUp follows at the first solve */
  MatNullSpaceDestroy(&nullspace);
  for (PetscInt k = 0; k < 16; k++) VecDestroy(&near[k]);
  ISDestroy(&fields[0]);
  ISDestroy(&fields[1]);
  *out = s;
  return 0;
fail:
  MatNullSpaceDestroy(&nullspace);
  for (PetscInt k = 0; k < 16; k++) VecDestroy(&near[k]);
  ISDestroy(&fields[0]);
  ISDestroy(&fields[1]);
  if (s) {
    KSPDestroy(&s->ksp);
    MatDestroy(&s->A);
    free(s);
  }
  return (int)code;
}

/* Every rank: the system of the command from this rank's rows (local CSR
 * with global columns) and its part of the near-nullspace vectors (the
 * first-field rows of each, `stride` apart). */
static int create_here(const command *c, PetscInt rstart, PetscInt m, const PetscInt *rowptr, const PetscInt *cols,
                       const PetscScalar *vals, const PetscScalar *modes, size_t stride, seam_petsc_system **out,
                       char *err, size_t errlen)
{
  Mat            A = NULL;
  double         t0 = now();
  PetscErrorCode code = build_matrix(c->n, rstart, m, c->n_first < c->n ? 1 : c->bs, rowptr, cols, vals,
                                     c->symmetric, 1, &A);
  *out = NULL;
  if (code) {
    message(code, err, errlen);
    return (int)code;
  }
  return configure_here(c, rstart, m, A, now() - t0, modes, stride, out, err, errlen);
}

static void destroy_here(seam_petsc_system *s)
{
  if (!s) return;
  KSPDestroy(&s->ksp);
  MatDestroy(&s->op);
  MatDestroy(&s->A);
  free(s->ranges);
  free(s);
}

/* The leader sends rank r the m rows from r0 of a CSR matrix (their offsets
 * from 0, columns and values), which the follower receives in this order. */
static void send_rows(const PetscInt *rowptr, const PetscInt *cols, const PetscScalar *vals, PetscInt r0, PetscInt m,
                      int r)
{
  PetscInt *local = (PetscInt *)malloc(((size_t)m + 1) * sizeof(PetscInt));
  if (!local) MPI_Abort(MPI_COMM_WORLD, 2); /* the followers wait for these rows */
  for (PetscInt i = 0; i <= m; i++) local[i] = rowptr[r0 + i] - rowptr[r0];
  send_array(local, (size_t)m + 1, MPIU_INT, sizeof(PetscInt), r);
  free(local);
  send_array(cols + rowptr[r0], (size_t)(rowptr[r0 + m] - rowptr[r0]), MPIU_INT, sizeof(PetscInt), r);
  send_array(vals + rowptr[r0], (size_t)(rowptr[r0 + m] - rowptr[r0]), MPIU_SCALAR, sizeof(PetscScalar), r);
}

/* The leader's command that creates a system (a new id). */
static command system_command(int cmd, PetscInt n, PetscInt n_first, PetscInt bs, PetscInt n_modes, PetscInt max_it,
                              int symmetric, double rtol, const char *ksp_type, const char *pc_type)
{
  command c;
  memset(&c, 0, sizeof(c));
  c.cmd       = cmd;
  c.id        = next_id++;
  c.n         = n;
  c.n_first   = n_first;
  c.bs        = bs;
  c.n_modes   = n_modes;
  c.max_it    = max_it;
  c.symmetric = symmetric;
  c.rtol      = rtol;
  snprintf(c.ksp_type, sizeof(c.ksp_type), "%s", ksp_type);
  snprintf(c.pc_type, sizeof(c.pc_type), "%s", pc_type);
  return c;
}

/* Builds the n × n matrix (CSR, 0-based, sorted columns; block size bs) as
 * AIJ (or what -mat_type chooses), the n_modes vectors at `modes` (n_first
 * entries each, one after the other, orthonormal; the rigid-body modes for
 * elasticity) as its near-nullspace, and a KSP of `ksp_type` with `pc_type`
 * (defaults that options override), relative tolerance rtol and at most
 * max_it iterations. The leader sends each follower its rows first. */
int seam_petsc_system_create(PetscInt n, PetscInt n_first, PetscInt bs, const PetscInt *rowptr,
                             const PetscInt *cols, const PetscScalar *vals, const PetscScalar *modes,
                             PetscInt n_modes, int symmetric, const char *ksp_type, const char *pc_type, double rtol,
                             PetscInt max_it, seam_petsc_system **out, char *err, size_t errlen)
{
  int       size = distributed() ? world_size() : 1, code;
  command   c;
  PetscInt *ranges = (PetscInt *)calloc((size_t)size + 1, sizeof(PetscInt));
  *out = NULL;
  if (!ranges) {
    snprintf(err, errlen, "out of memory");
    return PETSC_ERR_MEM;
  }
  c = system_command(CMD_CREATE, n, n_first, bs, n_modes, max_it, symmetric, rtol, ksp_type, pc_type);
  partition_rows(n, n_first, bs, rowptr, size, ranges);
  if (size > 1) {
    broadcast(&c);
    (void)MPI_Bcast(ranges, (size + 1) * (int)sizeof(PetscInt), MPI_BYTE, 0, MPI_COMM_WORLD);
    for (int r = 1; r < size; r++) {
      PetscInt r0 = ranges[r], m = ranges[r + 1] - r0, m_first = first_part(n_first, r0, m);
      send_rows(rowptr, cols, vals, r0, m, r);
      for (PetscInt k = 0; k < n_modes; k++)
        send_array(modes + (size_t)k * (size_t)n_first + r0, (size_t)m_first, MPIU_SCALAR, sizeof(PetscScalar), r);
    }
  }
  code = create_here(&c, 0, ranges[1], rowptr, cols, vals, modes, (size_t)n_first, out, err, errlen);
  if (!agreed(code)) {
    if (!code) {
      snprintf(err, errlen, "PETSc failed on another MPI rank while building the system");
      code = PETSC_ERR_LIB;
    }
    destroy_here(*out);
    *out = NULL;
    free(ranges);
    return code;
  }
  (*out)->ranges = ranges;
  return 0;
}

/* ---- Work of the program's own, handed out by the leader ----
 *
 * The leader sends each follower a byte array (seam_petsc_send_jobs); the
 * follower's seam_petsc_follow returns 2 with it, the follower does the work
 * and answers with a byte array (seam_petsc_reply), which the leader
 * collects (seam_petsc_receive_reply) after doing its own part. */

/* Sends parts[r − 1] (lens[r − 1] bytes) to rank r, for every follower. */
void seam_petsc_send_jobs(const unsigned char *const *parts, const size_t *lens)
{
  int size = distributed() ? world_size() : 1;
  if (size == 1 || released) return;
  command c;
  memset(&c, 0, sizeof(c));
  c.cmd = CMD_JOB;
  broadcast(&c);
  for (int r = 1; r < size; r++) {
    long long len = (long long)lens[r - 1];
    (void)MPI_Send(&len, 1, MPI_LONG_LONG, r, TAG, MPI_COMM_WORLD);
    send_array(parts[r - 1], lens[r - 1], MPI_BYTE, 1, r);
  }
}

/* A follower answers its job. */
void seam_petsc_reply(const unsigned char *bytes, size_t len)
{
  long long l = (long long)len;
  (void)MPI_Send(&l, 1, MPI_LONG_LONG, 0, TAG, MPI_COMM_WORLD);
  send_array(bytes, len, MPI_BYTE, 1, 0);
}

/* The leader: rank r's answer, in a buffer to release with
 * seam_petsc_release_bytes (NULL when empty or out of memory: *len says
 * which). Waits by testing every 0.2 ms, not in MPI's spinning receive. */
unsigned char *seam_petsc_receive_reply(int r, size_t *len)
{
  long long l = 0;
  int       arrived = 0;
  for (;;) {
    (void)MPI_Iprobe(r, TAG, MPI_COMM_WORLD, &arrived, MPI_STATUS_IGNORE);
    if (arrived) break;
    struct timespec pause = {0, 200000};
    nanosleep(&pause, NULL);
  }
  (void)MPI_Recv(&l, 1, MPI_LONG_LONG, r, TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  unsigned char *bytes = (unsigned char *)malloc((size_t)l + 1);
  if (!bytes) MPI_Abort(MPI_COMM_WORLD, 2); /* rank r waits to send */
  receive_array(bytes, (size_t)l, MPI_BYTE, 1, r);
  *len = (size_t)l;
  return bytes;
}

/* Frees a buffer of this layer (a job, an answer). */
void seam_petsc_release_bytes(unsigned char *bytes)
{
  free(bytes);
}

/* ---- A matrix assembled where its cells are ----
 *
 * Each rank stages its cells' entries (i, j, value: global indices, any row,
 * repeated entries summed) before the leader calls
 * seam_petsc_system_create_staged; the entries of rows held elsewhere go to
 * their ranks (pairwise exchanges), each rank sums its rows' entries in a
 * fixed order and builds its rows as in seam_petsc_system_create. */
static PetscInt    *staged_i = NULL, *staged_j = NULL;
static PetscScalar *staged_v = NULL;
static size_t       staged = 0;

static void unstage(void)
{
  free(staged_i);
  free(staged_j);
  free(staged_v);
  staged_i = staged_j = NULL;
  staged_v = NULL;
  staged   = 0;
}

/* Room for this rank's `count` entries (replacing any staged before):
 * the caller fills *i, *j, *v. Returns 0, or 1 when out of memory. */
int seam_petsc_stage(size_t count, PetscInt **i, PetscInt **j, PetscScalar **v)
{
  unstage();
  staged_i = (PetscInt *)malloc((count + 1) * sizeof(PetscInt));
  staged_j = (PetscInt *)malloc((count + 1) * sizeof(PetscInt));
  staged_v = (PetscScalar *)malloc((count + 1) * sizeof(PetscScalar));
  if (!staged_i || !staged_j || !staged_v) {
    unstage();
    return 1;
  }
  staged = count;
  *i = staged_i, *j = staged_j, *v = staged_v;
  return 0;
}

/* Sends `count` elements of `size` bytes to rank `to` while receiving
 * `expected` from rank `from` (MPI_Sendrecv in chunks of at most CHUNK
 * elements, whose counts are ints; `from` sends as many chunks as this
 * rank receives). */
static void exchange(const void *out, size_t count, int to, void *in, size_t expected, int from, MPI_Datatype type,
                     size_t size)
{
  const char *o = (const char *)out;
  char       *i = (char *)in;
  for (size_t done = 0; done < count || done < expected; done += CHUNK) {
    size_t k = done < count ? (count - done < CHUNK ? count - done : CHUNK) : 0;
    size_t l = done < expected ? (expected - done < CHUNK ? expected - done : CHUNK) : 0;
    /* A side with nothing left talks to no rank (no empty messages). */
    (void)MPI_Sendrecv(o + (k ? done * size : 0), (int)k, type, k ? to : MPI_PROC_NULL, TAG,
                       i + (l ? done * size : 0), (int)l, type, l ? from : MPI_PROC_NULL, TAG, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE);
  }
}

/* This rank's rows [r0, r0 + m) of the matrix every rank staged, as CSR
 * (sorted columns, repeated entries summed): the staged entries of rows
 * held elsewhere are sent to their ranks (`ranges`), those received added
 * (this rank's first, then the others' in rank order) and summed in an
 * order that the entries fix: the same sums for the same ranks. Frees the
 * staged entries. Returns
 * 0, or 1 when out of memory on one process (over ranks that aborts the
 * job, as a follower's missing buffer does). */
static int gather_rows(const PetscInt *ranges, PetscInt r0, PetscInt m, PetscInt **rowptr_out, PetscInt **cols_out,
                       PetscScalar **vals_out)
{
  int          size = world_size(), rank = world_rank(), failed = 0;
  long long   *to = (long long *)calloc((size_t)size, sizeof(long long));
  long long   *from = (long long *)calloc((size_t)size, sizeof(long long));
  size_t      *at = (size_t *)calloc((size_t)size + 1, sizeof(size_t));
  size_t       total = 0, received = 0;
  PetscInt    *ri = NULL, *rj = NULL, *rowptr = NULL, *cols = NULL, *fill = NULL;
  PetscScalar *rv = NULL, *vals = NULL;
  if (!to || !from || !at) goto oom;
  /* Entries by destination rank, this rank's first (a stable counting sort). */
  for (size_t e = 0; e < staged; e++) {
    int r = 0;
    PetscInt lo = 0, hi = size; /* the rank whose rows hold staged_i[e] */
    while (hi - lo > 1) {
      PetscInt mid = (lo + hi) / 2;
      if (ranges[mid] <= staged_i[e]) lo = mid;
      else hi = mid;
    }
    r = (int)lo;
    to[r]++;
  }
  if (size > 1) (void)MPI_Alltoall(to, 1, MPI_LONG_LONG, from, 1, MPI_LONG_LONG, MPI_COMM_WORLD);
  else from[0] = to[0];
  /* Send buffers in destination order. */
  {
    PetscInt    *si = (PetscInt *)malloc((staged + 1) * sizeof(PetscInt));
    PetscInt    *sj = (PetscInt *)malloc((staged + 1) * sizeof(PetscInt));
    PetscScalar *sv = (PetscScalar *)malloc((staged + 1) * sizeof(PetscScalar));
    size_t      *put = (size_t *)calloc((size_t)size + 1, sizeof(size_t));
    if (!si || !sj || !sv || !put) {
      free(si), free(sj), free(sv), free(put);
      goto oom;
    }
    for (int r = 0; r < size; r++) at[r + 1] = at[r] + (size_t)to[r];
    for (int r = 0; r < size; r++) put[r] = at[r];
    for (size_t e = 0; e < staged; e++) {
      PetscInt lo = 0, hi = size;
      while (hi - lo > 1) {
        PetscInt mid = (lo + hi) / 2;
        if (ranges[mid] <= staged_i[e]) lo = mid;
        else hi = mid;
      }
      size_t k = put[lo]++;
      si[k] = staged_i[e], sj[k] = staged_j[e], sv[k] = staged_v[e];
    }
    free(put);
    unstage();
    for (int r = 0; r < size; r++) received += (size_t)from[r];
    ri = (PetscInt *)malloc((received + 1) * sizeof(PetscInt));
    rj = (PetscInt *)malloc((received + 1) * sizeof(PetscInt));
    rv = (PetscScalar *)malloc((received + 1) * sizeof(PetscScalar));
    if (!ri || !rj || !rv) {
      free(si), free(sj), free(sv);
      goto oom;
    }
    /* Received entries in rank order: this rank's own, then rank 0, 1, …
     * (skipping this one), each exchange pairwise in steps. */
    size_t *start = (size_t *)calloc((size_t)size + 1, sizeof(size_t));
    if (!start) {
      free(si), free(sj), free(sv);
      goto oom;
    }
    {
      size_t k = (size_t)from[rank];
      start[rank] = 0;
      for (int r = 0; r < size; r++)
        if (r != rank) start[r] = k, k += (size_t)from[r];
    }
    memcpy(ri, si + at[rank], (size_t)to[rank] * sizeof(PetscInt));
    memcpy(rj, sj + at[rank], (size_t)to[rank] * sizeof(PetscInt));
    memcpy(rv, sv + at[rank], (size_t)to[rank] * sizeof(PetscScalar));
    for (int step = 1; step < size; step++) {
      int dst = (rank + step) % size, src = (rank - step + size) % size;
      exchange(si + at[dst], (size_t)to[dst], dst, ri + start[src], (size_t)from[src], src, MPIU_INT, sizeof(PetscInt));
      exchange(sj + at[dst], (size_t)to[dst], dst, rj + start[src], (size_t)from[src], src, MPIU_INT, sizeof(PetscInt));
      exchange(sv + at[dst], (size_t)to[dst], dst, rv + start[src], (size_t)from[src], src, MPIU_SCALAR,
               sizeof(PetscScalar));
    }
    free(start);
    free(si), free(sj), free(sv);
  }
  /* CSR of the received entries: by row (stable), then each row's columns
   * sorted and summed. */
  rowptr = (PetscInt *)calloc((size_t)m + 2, sizeof(PetscInt));
  fill = (PetscInt *)calloc((size_t)m + 1, sizeof(PetscInt));
  if (!rowptr || !fill) goto oom;
  for (size_t e = 0; e < received; e++) {
    PetscInt row = ri[e] - r0;
    if (row < 0 || row >= m) continue; /* not this rank's: cannot happen */
    rowptr[row + 1]++;
  }
  for (PetscInt r = 0; r < m; r++) rowptr[r + 1] += rowptr[r];
  total = (size_t)rowptr[m];
  cols = (PetscInt *)malloc((total + 1) * sizeof(PetscInt));
  vals = (PetscScalar *)malloc((total + 1) * sizeof(PetscScalar));
  if (!cols || !vals) goto oom;
  for (size_t e = 0; e < received; e++) {
    PetscInt row = ri[e] - r0;
    if (row < 0 || row >= m) continue;
    size_t k = (size_t)(rowptr[row] + fill[row]++);
    cols[k] = rj[e], vals[k] = rv[e];
  }
  free(ri), free(rj), free(rv);
  ri = rj = NULL;
  rv = NULL;
  {
    /* Per row: sort by column (PETSc's sort: the same order for the same
     * entries), then sum repeats in place; rows are compacted as they go. */
    PetscInt out = 0;
    for (PetscInt r = 0; r < m; r++) {
      PetscInt a = rowptr[r], b = rowptr[r + 1];
      (void)PetscSortIntWithScalarArray(b - a, cols + a, vals + a);
      rowptr[r] = out;
      for (PetscInt k = a; k < b; k++) {
        if (out > rowptr[r] && cols[out - 1] == cols[k]) vals[out - 1] += vals[k];
        else cols[out] = cols[k], vals[out] = vals[k], out++;
      }
    }
    rowptr[m] = out;
  }
  free(fill);
  free(to), free(from), free(at);
  *rowptr_out = rowptr, *cols_out = cols, *vals_out = vals;
  return 0;
oom:
  /* The other ranks wait in the exchanges for this one: as for the
   * leader's data, a buffer that cannot be had aborts the MPI job. */
  if (size > 1) MPI_Abort(MPI_COMM_WORLD, 2);
  failed = 1;
  unstage();
  free(to), free(from), free(at), free(ri), free(rj), free(rv), free(rowptr), free(cols), free(vals), free(fill);
  return failed;
}

/* Every rank: the system of the command from every rank's staged entries
 * (this rank's rows [r0, r0 + m) of `ranges`) and this rank's first-field
 * rows of the near-nullspace vectors (one after the other). */
static int staged_here(const command *c, const PetscInt *ranges, PetscInt r0, PetscInt m, const PetscScalar *modes,
                       seam_petsc_system **out, char *err, size_t errlen)
{
  PetscErrorCode code = 0;
  Mat            A = NULL;
  PetscInt      *rowptr = NULL, *cols = NULL;
  PetscScalar   *vals = NULL;
  double         t0 = now();

  *out = NULL;
  if (gather_rows(ranges, r0, m, &rowptr, &cols, &vals)) {
    snprintf(err, errlen, "out of memory gathering the matrix's rows");
    return PETSC_ERR_MEM;
  }
  TRY(build_matrix(c->n, r0, m, c->n_first < c->n ? 1 : c->bs, rowptr, cols, vals, c->symmetric, 1, &A));
  free(rowptr), free(cols), free(vals);
  return configure_here(c, r0, m, A, now() - t0, modes, (size_t)first_part(c->n_first, r0, m), out, err, errlen);
fail:
  free(rowptr), free(cols), free(vals);
  MatDestroy(&A);
  return (int)code;
}

/* The n × n matrix whose entries every rank staged (seam_petsc_stage:
 * summed where repeated, each sent to the rank that holds its row), never
 * whole on one rank: rank r holds rows [ranges[r], ranges[r + 1]) (whole
 * points of bs rows below n_first), the leader gives the n_modes
 * near-nullspace vectors (n_first entries each); a saddle point when
 * n_first < n, and the KSP, as by seam_petsc_system_create. */
int seam_petsc_system_create_staged(PetscInt n, PetscInt n_first, PetscInt bs, const PetscInt *ranges,
                                    const PetscScalar *modes, PetscInt n_modes, int symmetric, const char *ksp_type,
                                    const char *pc_type, double rtol, PetscInt max_it, seam_petsc_system **out,
                                    char *err, size_t errlen)
{
  int          size = distributed() ? world_size() : 1, code;
  command      c;
  PetscInt    *kept = (PetscInt *)calloc((size_t)size + 1, sizeof(PetscInt));
  PetscInt     own_first = first_part(n_first, 0, ranges[1]);
  PetscScalar *own = (PetscScalar *)malloc(((size_t)n_modes * (size_t)own_first + 1) * sizeof(PetscScalar));
  *out = NULL;
  if (!kept || !own) {
    free(kept);
    free(own);
    snprintf(err, errlen, "out of memory");
    return PETSC_ERR_MEM;
  }
  memcpy(kept, ranges, ((size_t)size + 1) * sizeof(PetscInt));
  c = system_command(CMD_STAGED, n, n_first, bs, n_modes, max_it, symmetric, rtol, ksp_type, pc_type);
  if (size > 1) {
    broadcast(&c);
    (void)MPI_Bcast(kept, (size + 1) * (int)sizeof(PetscInt), MPI_BYTE, 0, MPI_COMM_WORLD);
    for (int r = 1; r < size; r++)
      for (PetscInt k = 0; k < n_modes; k++)
        send_array(modes + (size_t)k * (size_t)n_first + kept[r],
                   (size_t)first_part(n_first, kept[r], kept[r + 1] - kept[r]), MPIU_SCALAR, sizeof(PetscScalar), r);
  }
  for (PetscInt k = 0; k < n_modes; k++)
    memcpy(own + (size_t)k * own_first, modes + (size_t)k * n_first, (size_t)own_first * sizeof(PetscScalar));
  code = staged_here(&c, kept, 0, kept[1], own, out, err, errlen);
  free(own);
  if (!agreed(code)) {
    if (!code) {
      snprintf(err, errlen, "PETSc failed on another MPI rank while building the system");
      code = PETSC_ERR_LIB;
    }
    destroy_here(*out);
    *out = NULL;
    free(kept);
    return code;
  }
  (*out)->ranges = kept;
  return 0;
}

/* A follower's part of seam_petsc_system_create_staged. */
static int follow_staged(const command *c, seam_petsc_system **s, char *err, size_t errlen)
{
  int       size = world_size(), rank = world_rank(), code;
  PetscInt *ranges = (PetscInt *)calloc((size_t)size + 1, sizeof(PetscInt));
  if (!ranges) MPI_Abort(MPI_COMM_WORLD, 2);
  (void)MPI_Bcast(ranges, (size + 1) * (int)sizeof(PetscInt), MPI_BYTE, 0, MPI_COMM_WORLD);
  PetscInt     r0 = ranges[rank], m = ranges[rank + 1] - r0, m_first = first_part(c->n_first, r0, m);
  PetscScalar *modes = (PetscScalar *)malloc(((size_t)c->n_modes * (size_t)m_first + 1) * sizeof(PetscScalar));
  if (!modes) MPI_Abort(MPI_COMM_WORLD, 2);
  for (PetscInt k = 0; k < c->n_modes; k++)
    receive_array(modes + (size_t)k * (size_t)m_first, (size_t)m_first, MPIU_SCALAR, sizeof(PetscScalar), 0);
  code = staged_here(c, ranges, r0, m, modes, s, err, errlen);
  free(modes);
  free(ranges);
  return code;
}

/* Every rank: solves with this rank's rows of b and x. */
static int solve_here(seam_petsc_system *s, const PetscScalar *b, PetscScalar *x, int nonzero_guess, double rtol,
                      seam_petsc_report *report, char *err, size_t errlen)
{
  PetscErrorCode     code = 0;
  Vec                vb = NULL, vx = NULL;
  PC                 pc;
  KSPType            kt;
  PCType             pt;
  KSPConvergedReason reason;
  double             t0;

  memset(report, 0, sizeof(*report));
  report->ranks = world_size();
  TRY(VecCreateMPIWithArray(PETSC_COMM_WORLD, s->bs, s->m, s->n, b, &vb));
  TRY(VecCreateMPIWithArray(PETSC_COMM_WORLD, s->bs, s->m, s->n, x, &vx));
  TRY(KSPSetInitialGuessNonzero(s->ksp, nonzero_guess ? PETSC_TRUE : PETSC_FALSE));
  TRY(KSPSetTolerances(s->ksp, rtol > 0 ? rtol : s->rtol, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
  t0 = now();
  TRY(KSPSetUp(s->ksp));
  s->setup_seconds += now() - t0;
  t0 = now();
  TRY(KSPSolve(s->ksp, vb, vx));
  report->solve_seconds = now() - t0;
  /* The seconds since the last report (a second solve counts no setup). */
  report->setup_seconds    = s->setup_seconds;
  report->assembly_seconds = s->assembly_seconds;
  s->setup_seconds = s->assembly_seconds = 0;
  {
    Mat       op;
    Vec       r;
    PetscReal rn, bn;
    TRY(KSPGetOperators(s->ksp, &op, NULL));
    TRY(VecDuplicate(vb, &r));
    TRY(MatMult(op, vx, r));
    TRY(VecAYPX(r, -1.0, vb));
    TRY(VecNorm(r, NORM_2, &rn));
    TRY(VecNorm(vb, NORM_2, &bn));
    TRY(VecDestroy(&r));
    report->true_residual = bn > 0 ? rn / bn : rn;
  }
  TRY(KSPGetIterationNumber(s->ksp, &report->iterations));
  TRY(KSPGetResidualNorm(s->ksp, &report->ksp_residual));
  TRY(KSPGetConvergedReason(s->ksp, &reason));
  report->reason = (int)reason;
  snprintf(report->reason_name, sizeof(report->reason_name), "%s", KSPConvergedReasons[reason]);
  TRY(KSPGetType(s->ksp, &kt));
  TRY(KSPGetPC(s->ksp, &pc));
  TRY(PCGetType(pc, &pt));
  snprintf(report->ksp_type, sizeof(report->ksp_type), "%s", kt ? kt : "");
  snprintf(report->pc_type, sizeof(report->pc_type), "%s", pt ? pt : "");
  VecDestroy(&vb);
  VecDestroy(&vx);
  return 0;
fail:
  VecDestroy(&vb);
  VecDestroy(&vx);
  return (int)code;
}

/* Solves A x = b (n entries each, on the leader); x holds the initial guess
 * when nonzero_guess. The followers get their rows of b and x, and send
 * their rows of the solution back. */
int seam_petsc_system_solve(seam_petsc_system *s, const PetscScalar *b, PetscScalar *x, int nonzero_guess,
                            double rtol, seam_petsc_report *report, char *err, size_t errlen)
{
  int size = distributed() ? world_size() : 1, code;
  if (size > 1) {
    command c;
    memset(&c, 0, sizeof(c));
    c.cmd           = CMD_SOLVE;
    c.id            = s->id;
    c.nonzero_guess = nonzero_guess;
    c.rtol          = rtol;
    broadcast(&c);
    for (int r = 1; r < size; r++) {
      size_t r0 = (size_t)s->ranges[r], m = (size_t)(s->ranges[r + 1] - s->ranges[r]);
      send_array(b + r0, m, MPIU_SCALAR, sizeof(PetscScalar), r);
      send_array(x + r0, m, MPIU_SCALAR, sizeof(PetscScalar), r);
    }
  }
  code = solve_here(s, b, x, nonzero_guess, rtol, report, err, errlen);
  for (int r = 1; r < size; r++) {
    size_t r0 = (size_t)s->ranges[r], m = (size_t)(s->ranges[r + 1] - s->ranges[r]);
    receive_array(x + r0, m, MPIU_SCALAR, sizeof(PetscScalar), r);
  }
  if (!agreed(code) && !code) {
    snprintf(err, errlen, "PETSc failed on another MPI rank during the solve");
    code = PETSC_ERR_LIB;
  }
  return code;
}

/* The system's matrix has new values (since t0): it is the operator again,
 * and the next solve sets the preconditioner up for it. */
static int refreshed(seam_petsc_system *s, double t0, char *err, size_t errlen)
{
  PetscErrorCode code = 0;
  MatDestroy(&s->op);
  TRY(KSPSetOperators(s->ksp, s->A, s->A));
  TRY(KSPSetReusePreconditioner(s->ksp, PETSC_FALSE));
  s->assembly_seconds += now() - t0;
  return 0;
fail:
  return (int)code;
}

/* Every rank: this rank's rows of a new operator (same size and layout as
 * the system's matrix). Kept (refresh 0): any pattern; the next solves apply
 * it while the preconditioner stays the one set up for the system's matrix.
 * Refreshed (refresh 1): the values of the system's matrix itself, in the
 * pattern it was built with (an entry outside it is an error); it is the
 * operator again, and the next solve sets the preconditioner up for it —
 * GAMG keeping its interpolation (PCGAMGSetReuseInterpolation, set at the
 * creation unless the options say otherwise): only the Galerkin products
 * and the smoothers are formed again. */
static int operator_here(seam_petsc_system *s, const PetscInt *rowptr, const PetscInt *cols, const PetscScalar *vals,
                         int refresh, char *err, size_t errlen)
{
  PetscErrorCode code = 0;
  Mat            B = NULL;
  double         t0 = now();
  if (refresh) {
    TRY(MatSetOption(s->A, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
    TRY(MatZeroEntries(s->A));
    for (PetscInt i = 0; i < s->m; i++) {
      PetscInt row = s->rstart + i;
      TRY(MatSetValues(s->A, 1, &row, rowptr[i + 1] - rowptr[i], cols + rowptr[i], vals + rowptr[i], INSERT_VALUES));
    }
    TRY(MatAssemblyBegin(s->A, MAT_FINAL_ASSEMBLY));
    TRY(MatAssemblyEnd(s->A, MAT_FINAL_ASSEMBLY));
    return refreshed(s, t0, err, errlen);
  }
  code = build_matrix(s->n, s->rstart, s->m, s->bs, rowptr, cols, vals, 0, 1, &B);
  if (code) {
    message(code, err, errlen);
    return (int)code;
  }
  MatDestroy(&s->op);
  s->op = B;
  TRY(KSPSetOperators(s->ksp, s->op, s->A));
  TRY(KSPSetReusePreconditioner(s->ksp, PETSC_TRUE));
  s->assembly_seconds += now() - t0;
  return 0;
fail:
  return (int)code;
}

/* Replaces the operator of `s` by the n × n matrix (CSR on the leader, as
 * for seam_petsc_system_create), keeping the preconditioner, or refreshes
 * the system's matrix with new values in its pattern (operator_here): the
 * followers get their rows first. */
int seam_petsc_system_set_operator(seam_petsc_system *s, const PetscInt *rowptr, const PetscInt *cols,
                                   const PetscScalar *vals, int refresh, char *err, size_t errlen)
{
  int size = distributed() ? world_size() : 1, code;
  if (size > 1) {
    command c;
    memset(&c, 0, sizeof(c));
    c.cmd       = CMD_OPERATOR;
    c.id        = s->id;
    c.symmetric = refresh;
    broadcast(&c);
    for (int r = 1; r < size; r++) send_rows(rowptr, cols, vals, s->ranges[r], s->ranges[r + 1] - s->ranges[r], r);
  }
  code = operator_here(s, rowptr, cols, vals, refresh, err, errlen);
  if (!agreed(code) && !code) {
    snprintf(err, errlen, "PETSc failed on another MPI rank while replacing the operator");
    code = PETSC_ERR_LIB;
  }
  return code;
}

/* One process, an AIJ matrix: the array of the system's values in its
 * compressed rows (columns ascending within a row), *count entries, for the
 * caller to write new values into before seam_petsc_system_values_written;
 * NULL (and 0) on several ranks or for another matrix type. */
int seam_petsc_system_values(seam_petsc_system *s, PetscScalar **values, PetscInt *count, char *err, size_t errlen)
{
  PetscErrorCode code = 0;
  PetscBool      seqaij = PETSC_FALSE;
  MatInfo        info;
  *values = NULL;
  *count  = 0;
  if (distributed() && world_size() > 1) return 0;
  TRY(PetscObjectTypeCompare((PetscObject)s->A, MATSEQAIJ, &seqaij));
  if (!seqaij) return 0;
  TRY(MatGetInfo(s->A, MAT_LOCAL, &info));
  {
    PetscScalar *a = NULL; /* the array stays where it is; the pair is balanced */
    TRY(MatSeqAIJGetArray(s->A, &a));
    *values = a;
    TRY(MatSeqAIJRestoreArray(s->A, &a));
  }
  *count = (PetscInt)info.nz_used;
  return 0;
fail:
  return (int)code;
}

/* The values written (seam_petsc_system_values): the system's matrix is the
 * operator again and the next solve refreshes the preconditioner, as
 * operator_here's refresh does. */
int seam_petsc_system_values_written(seam_petsc_system *s, char *err, size_t errlen)
{
  PetscErrorCode code = 0;
  PetscScalar   *values = NULL;
  double         t0 = now();
  TRY(MatSeqAIJGetArray(s->A, &values)); /* restoring it marks the matrix changed */
  TRY(MatSeqAIJRestoreArray(s->A, &values));
  return refreshed(s, t0, err, errlen);
fail:
  return (int)code;
}

void seam_petsc_system_destroy(seam_petsc_system *s)
{
  PetscBool finalized = PETSC_FALSE;
  if (!s) return;
  PetscFinalized(&finalized);
  if (finalized) { /* PETSc's objects went with it; so did the followers */
    free(s->ranges);
    free(s);
    return;
  }
  if (distributed()) {
    command c;
    memset(&c, 0, sizeof(c));
    c.cmd = CMD_DESTROY;
    c.id  = s->id;
    broadcast(&c);
  }
  destroy_here(s);
}

/* A follower's system of each id (ids are consecutive from 0). */
typedef struct {
  seam_petsc_system **at;
  size_t              len;
} systems;

static int keep(systems *all, seam_petsc_system *s)
{
  if ((size_t)s->id >= all->len) {
    size_t              len = 2 * (size_t)s->id + 8;
    seam_petsc_system **at = (seam_petsc_system **)realloc(all->at, len * sizeof(*at));
    if (!at) return 0;
    memset(at + all->len, 0, (len - all->len) * sizeof(*at));
    all->at = at, all->len = len;
  }
  all->at[s->id] = s;
  return 1;
}

static seam_petsc_system *find(const systems *all, int id)
{
  return id >= 0 && (size_t)id < all->len ? all->at[id] : NULL;
}

/* The leader hands its followers back to their caller for other work
 * (seam_petsc_follow returns 1 there); they come back by following again. */
void seam_petsc_yield(void)
{
  if (distributed() && !released) {
    command c;
    memset(&c, 0, sizeof(c));
    c.cmd = CMD_YIELD;
    broadcast(&c);
  }
}

/* A follower's systems, kept between its calls of seam_petsc_follow. */
static systems all = {NULL, 0};

/* A follower (a rank other than 0, whose rank 0 called seam_petsc_lead):
 * carries out the leader's calls until the leader finalises (returns 0) or
 * yields (returns 1: the caller does the leader's other work, then follows
 * again) or sends a job (returns 2 with *job, *job_len bytes to release with
 * seam_petsc_release_bytes: the caller does it, answers with
 * seam_petsc_reply and follows again). Waits for each command by testing every 0.2 ms, not in MPI's
 * blocking wait, which spins: the leader may compute for long between
 * calls. *failed is the last error code of a command that failed here (the
 * leader has been told), else 0. A buffer for the leader's data that cannot
 * be allocated aborts the MPI job (the leader would wait for this rank
 * forever otherwise). */
int seam_petsc_follow(int *failed, unsigned char **job, size_t *job_len, char *err, size_t errlen)
{
  following = 1;
  for (;;) {
    command     c;
    MPI_Request request;
    int         done = 0, code = 0;
    (void)MPI_Ibcast(&c, (int)sizeof(c), MPI_BYTE, 0, MPI_COMM_WORLD, &request);
    for (MPI_Test(&request, &done, MPI_STATUS_IGNORE); !done; MPI_Test(&request, &done, MPI_STATUS_IGNORE)) {
      struct timespec pause = {0, 200000};
      nanosleep(&pause, NULL);
    }
    if (c.cmd == CMD_EXIT) {
      free(all.at);
      all.at = NULL, all.len = 0;
      return 0;
    }
    if (c.cmd == CMD_YIELD) return 1;
    if (c.cmd == CMD_JOB) {
      long long len = 0;
      (void)MPI_Recv(&len, 1, MPI_LONG_LONG, 0, TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      *job = (unsigned char *)malloc((size_t)len + 1);
      if (!*job) MPI_Abort(MPI_COMM_WORLD, 2); /* the leader waits for an answer */
      receive_array(*job, (size_t)len, MPI_BYTE, 1, 0);
      *job_len = (size_t)len;
      return 2;
    }
    if (c.cmd == CMD_INIT) {
      /* PETSc keeps pointers into argv: the words stay for the process. */
      char  *packed = (char *)malloc((size_t)c.bytes);
      char **argv = (char **)calloc((size_t)c.argc + 1, sizeof(char *));
      if (!packed || !argv) MPI_Abort(MPI_COMM_WORLD, 2);
      (void)MPI_Bcast(packed, (int)c.bytes, MPI_BYTE, 0, MPI_COMM_WORLD);
      char *p = packed;
      for (int k = 0; k < c.argc; k++, p += strlen(p) + 1) argv[k] = p;
      code = initialize_here(c.argc, argv, p, err, errlen);
      agreed(code);
    } else if (c.cmd == CMD_CREATE) {
      int                size = world_size(), rank = world_rank();
      PetscInt          *ranges = (PetscInt *)calloc((size_t)size + 1, sizeof(PetscInt));
      seam_petsc_system *s = NULL;
      if (!ranges) MPI_Abort(MPI_COMM_WORLD, 2);
      (void)MPI_Bcast(ranges, (size + 1) * (int)sizeof(PetscInt), MPI_BYTE, 0, MPI_COMM_WORLD);
      PetscInt r0 = ranges[rank], m = ranges[rank + 1] - r0, m_first = first_part(c.n_first, r0, m);
      free(ranges);
      PetscInt *rowptr = (PetscInt *)malloc(((size_t)m + 1) * sizeof(PetscInt));
      if (!rowptr) MPI_Abort(MPI_COMM_WORLD, 2);
      receive_array(rowptr, (size_t)m + 1, MPIU_INT, sizeof(PetscInt), 0);
      size_t       nnz = (size_t)rowptr[m];
      PetscInt    *cols = (PetscInt *)malloc((nnz + 1) * sizeof(PetscInt));
      PetscScalar *vals = (PetscScalar *)malloc((nnz + 1) * sizeof(PetscScalar));
      PetscScalar *modes = (PetscScalar *)malloc(((size_t)c.n_modes * (size_t)m_first + 1) * sizeof(PetscScalar));
      if (!cols || !vals || !modes) MPI_Abort(MPI_COMM_WORLD, 2);
      receive_array(cols, nnz, MPIU_INT, sizeof(PetscInt), 0);
      receive_array(vals, nnz, MPIU_SCALAR, sizeof(PetscScalar), 0);
      for (PetscInt k = 0; k < c.n_modes; k++)
        receive_array(modes + (size_t)k * (size_t)m_first, (size_t)m_first, MPIU_SCALAR, sizeof(PetscScalar), 0);
      code = create_here(&c, r0, m, rowptr, cols, vals, modes, (size_t)m_first, &s, err, errlen);
      free(rowptr);
      free(cols);
      free(vals);
      free(modes);
      if (!code && !keep(&all, s)) {
        snprintf(err, errlen, "out of memory");
        code = PETSC_ERR_MEM;
      }
      if (!agreed(code)) {
        if (s && find(&all, s->id) == s) all.at[s->id] = NULL;
        destroy_here(s);
      }
    } else if (c.cmd == CMD_STAGED) {
      seam_petsc_system *s = NULL;
      code = follow_staged(&c, &s, err, errlen);
      if (!code && !keep(&all, s)) {
        snprintf(err, errlen, "out of memory");
        code = PETSC_ERR_MEM;
      }
      if (!agreed(code)) {
        if (s && find(&all, s->id) == s) all.at[s->id] = NULL;
        destroy_here(s);
      }
    } else if (c.cmd == CMD_SOLVE) {
      seam_petsc_system *s = find(&all, c.id);
      seam_petsc_report  report;
      if (!s) MPI_Abort(MPI_COMM_WORLD, 2); /* the leader solves a system it has */
      PetscScalar *b = (PetscScalar *)malloc(((size_t)s->m + 1) * sizeof(PetscScalar));
      PetscScalar *x = (PetscScalar *)malloc(((size_t)s->m + 1) * sizeof(PetscScalar));
      if (!b || !x) MPI_Abort(MPI_COMM_WORLD, 2);
      receive_array(b, (size_t)s->m, MPIU_SCALAR, sizeof(PetscScalar), 0);
      receive_array(x, (size_t)s->m, MPIU_SCALAR, sizeof(PetscScalar), 0);
      code = solve_here(s, b, x, c.nonzero_guess, c.rtol, &report, err, errlen);
      send_array(x, (size_t)s->m, MPIU_SCALAR, sizeof(PetscScalar), 0);
      free(b);
      free(x);
      agreed(code);
    } else if (c.cmd == CMD_OPERATOR) {
      seam_petsc_system *s = find(&all, c.id);
      if (!s) MPI_Abort(MPI_COMM_WORLD, 2); /* the leader replaces the operator of a system it has */
      PetscInt *rowptr = (PetscInt *)malloc(((size_t)s->m + 1) * sizeof(PetscInt));
      if (!rowptr) MPI_Abort(MPI_COMM_WORLD, 2);
      receive_array(rowptr, (size_t)s->m + 1, MPIU_INT, sizeof(PetscInt), 0);
      size_t       nnz = (size_t)rowptr[s->m];
      PetscInt    *cols = (PetscInt *)malloc((nnz + 1) * sizeof(PetscInt));
      PetscScalar *vals = (PetscScalar *)malloc((nnz + 1) * sizeof(PetscScalar));
      if (!cols || !vals) MPI_Abort(MPI_COMM_WORLD, 2);
      receive_array(cols, nnz, MPIU_INT, sizeof(PetscInt), 0);
      receive_array(vals, nnz, MPIU_SCALAR, sizeof(PetscScalar), 0);
      code = operator_here(s, rowptr, cols, vals, c.symmetric, err, errlen);
      free(rowptr);
      free(cols);
      free(vals);
      agreed(code);
    } else if (c.cmd == CMD_DESTROY) {
      seam_petsc_system *s = find(&all, c.id);
      if (s) all.at[c.id] = NULL;
      destroy_here(s);
    }
    if (code) *failed = code;
  }
}
