/*
 * The C side of seam's PETSc layer: PETSc's API is macro-heavy (communicators,
 * error checking), so the few things seam needs are written here once, in C,
 * against PETSc's own headers, and called from Rust through five functions
 * (src/lib.rs). Every PETSc call is checked; an error returns its code and a
 * one-line message in the caller's buffer (PETSc's return-error handler is
 * pushed at initialisation, so nothing is printed). Single process:
 * PETSC_COMM_SELF.
 */
#include <petscksp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
} seam_petsc_report;

/* A matrix with its KSP, the preconditioner set up at the first solve (so
 * that the caller can free its copy of the matrix first), solved
 * with any number of right-hand sides. */
typedef struct {
  Mat A;
  KSP ksp;
  PetscInt n, bs;
  double assembly_seconds, setup_seconds;
} seam_petsc_system;

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

static void finalize_at_exit(void)
{
  PetscBool initialized = PETSC_FALSE, finalized = PETSC_FALSE;
  PetscInitialized(&initialized);
  PetscFinalized(&finalized);
  if (initialized && !finalized) PetscFinalize();
}

/* Finalises PETSc now if it was initialised (before the caller finalises an
 * MPI it initialised itself); the exit handler then does nothing. */
void seam_petsc_finalize(void)
{
  finalize_at_exit();
}

static double now(void)
{
  PetscLogDouble t = 0;
  PetscTime(&t);
  return (double)t;
}

/* Initialises PETSc (and MPI) once per process with the options in argv
 * (after PETSC_OPTIONS, which PETSc reads itself); PetscFinalize runs at
 * process exit (so that -log_view prints). Later calls insert their options
 * into the database. Returns 0 or an error code. */
int seam_petsc_initialize(int argc, char **argv, const char *more, int *world_size, char *err, size_t errlen)
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
  {
    PetscMPIInt size = 1;
    if (MPI_Comm_size(PETSC_COMM_WORLD, &size) != MPI_SUCCESS) size = -1;
    *world_size = (int)size;
  }
  return 0;
fail:
  return (int)code;
}

/* sizeof(PetscInt), for the Rust side to check its index type. */
int seam_petsc_petscint_size(void)
{
  return (int)sizeof(PetscInt);
}

/* The n × n matrix of the CSR arrays (0-based, sorted columns) as AIJ, or
 * what -mat_type chooses, with block size bs. */
static PetscErrorCode build_matrix(PetscInt n, PetscInt bs, const PetscInt *rowptr, const PetscInt *cols,
                                   const PetscScalar *vals, int symmetric, Mat *out)
{
  Mat       A;
  PetscInt *nnz, *bnnz, *mark;
  PetscBool sbaij = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(MatCreate(PETSC_COMM_SELF, &A));
  PetscCall(MatSetSizes(A, n, n, n, n));
  PetscCall(MatSetType(A, MATAIJ));
  PetscCall(MatSetBlockSize(A, bs));
  PetscCall(MatSetFromOptions(A));
  /* Preallocation for AIJ (entries per row) and BAIJ/SBAIJ (blocks per
   * block row); only the call of the matrix's type takes effect. */
  PetscCall(PetscMalloc1(n, &nnz));
  PetscCall(PetscCalloc1(n / bs + 1, &bnnz));
  PetscCall(PetscMalloc1(n / bs + 1, &mark));
  for (PetscInt r = 0; r <= n / bs; r++) mark[r] = -1;
  for (PetscInt i = 0; i < n; i++) {
    nnz[i] = rowptr[i + 1] - rowptr[i];
    for (PetscInt j = rowptr[i]; j < rowptr[i + 1]; j++) {
      PetscInt block = cols[j] / bs;
      if (mark[block] != i / bs) {
        mark[block] = i / bs;
        bnnz[i / bs]++;
      }
    }
  }
  PetscCall(MatSeqAIJSetPreallocation(A, 0, nnz));
  PetscCall(MatSeqBAIJSetPreallocation(A, bs, 0, bnnz));
  PetscCall(MatSeqSBAIJSetPreallocation(A, bs, 0, bnnz));
  PetscCall(PetscFree(nnz));
  PetscCall(PetscFree(bnnz));
  PetscCall(PetscFree(mark));
  PetscCall(MatSetOption(A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)A, &sbaij, MATSEQSBAIJ, MATSBAIJ, ""));
  if (sbaij) PetscCall(MatSetOption(A, MAT_IGNORE_LOWER_TRIANGULAR, PETSC_TRUE));
  for (PetscInt i = 0; i < n; i++)
    PetscCall(MatSetValues(A, 1, &i, rowptr[i + 1] - rowptr[i], cols + rowptr[i], vals + rowptr[i], INSERT_VALUES));
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  if (symmetric) PetscCall(MatSetOption(A, MAT_SYMMETRIC, PETSC_TRUE));
  *out = A;
  PetscFunctionReturn(0);
}

/* Builds the n × n matrix (CSR, 0-based, sorted columns; block size bs) as
 * AIJ (or what -mat_type chooses), the n_modes orthonormal vectors at
 * `modes` (n entries each, one after the other; the rigid-body modes for
 * elasticity) as its near-nullspace, and a KSP of
 * `ksp_type` with `pc_type` (defaults that options override), relative
 * tolerance rtol and at most max_it iterations; sets the preconditioner up. */
int seam_petsc_system_create(PetscInt n, PetscInt n_first, PetscInt bs, const PetscInt *rowptr,
                             const PetscInt *cols, const PetscScalar *vals, const PetscScalar *modes,
                             PetscInt n_modes, int symmetric, const char *ksp_type, const char *pc_type, double rtol,
                             PetscInt max_it, seam_petsc_system **out, char *err, size_t errlen)
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
  const PetscBool     split = n_first < n;
  const PetscInt      mat_bs = split ? 1 : bs;
  double              t0;

  *out = NULL;
  s = (seam_petsc_system *)calloc(1, sizeof(*s));
  if (!s) {
    snprintf(err, errlen, "out of memory");
    return PETSC_ERR_MEM;
  }
  s->n  = n;
  s->bs = mat_bs;
  t0    = now();
  TRY(build_matrix(n, mat_bs, rowptr, cols, vals, symmetric, &s->A));
  if (n_modes > 16) {
    snprintf(err, errlen, "at most 16 near-nullspace vectors, got %d", (int)n_modes);
    code = PETSC_ERR_ARG_OUTOFRANGE;
    goto fail;
  }
  for (PetscInt k = 0; k < n_modes; k++) {
    PetscScalar *a;
    TRY(VecCreateSeq(PETSC_COMM_SELF, n_first, &near[k]));
    TRY(VecSetBlockSize(near[k], bs));
    TRY(VecGetArray(near[k], &a));
    memcpy(a, modes + (size_t)k * (size_t)n_first, (size_t)n_first * sizeof(PetscScalar));
    TRY(VecRestoreArray(near[k], &a));
  }
  if (n_modes > 0) TRY(MatNullSpaceCreate(PETSC_COMM_SELF, PETSC_FALSE, n_modes, near, &nullspace));
  if (nullspace && !split) TRY(MatSetNearNullSpace(s->A, nullspace));
  s->assembly_seconds = now() - t0;
  t0 = now();
  TRY(KSPCreate(PETSC_COMM_SELF, &s->ksp));
  TRY(KSPSetOperators(s->ksp, s->A, s->A));
  TRY(KSPSetType(s->ksp, ksp_type));
  TRY(KSPGetPC(s->ksp, &pc));
  TRY(PCSetType(pc, pc_type));
  if (split) {
    PetscBool fieldsplit = PETSC_FALSE;
    TRY(ISCreateStride(PETSC_COMM_SELF, n_first, 0, 1, &fields[0]));
    TRY(ISSetBlockSize(fields[0], bs));
    TRY(ISCreateStride(PETSC_COMM_SELF, n - n_first, n_first, 1, &fields[1]));
    if (nullspace) TRY(PetscObjectCompose((PetscObject)fields[0], "nearnullspace", (PetscObject)nullspace));
    TRY(PetscObjectTypeCompare((PetscObject)pc, PCFIELDSPLIT, &fieldsplit));
    if (fieldsplit) {
      TRY(PCFieldSplitSetIS(pc, "0", fields[0]));
      TRY(PCFieldSplitSetIS(pc, "1", fields[1]));
      TRY(PCFieldSplitSetType(pc, PC_COMPOSITE_SCHUR));
      TRY(PCFieldSplitSetSchurFactType(pc, PC_FIELDSPLIT_SCHUR_FACT_FULL));
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
  TRY(KSPSetTolerances(s->ksp, rtol, PETSC_DEFAULT, PETSC_DEFAULT, max_it));
  TRY(KSPSetFromOptions(s->ksp));
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

/* Solves A x = b; x holds the initial guess when nonzero_guess. */
int seam_petsc_system_solve(seam_petsc_system *s, const PetscScalar *b, PetscScalar *x, int nonzero_guess,
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
  TRY(VecCreateSeqWithArray(PETSC_COMM_SELF, s->bs, s->n, b, &vb));
  TRY(VecCreateSeqWithArray(PETSC_COMM_SELF, s->bs, s->n, x, &vx));
  TRY(KSPSetInitialGuessNonzero(s->ksp, nonzero_guess ? PETSC_TRUE : PETSC_FALSE));
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

void seam_petsc_system_destroy(seam_petsc_system *s)
{
  if (!s) return;
  KSPDestroy(&s->ksp);
  MatDestroy(&s->A);
  free(s);
}
