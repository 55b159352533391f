/* Writes an Exodus II file with the SEACAS library (Debian libexodusii-dev),
 * then reads back the nodes of every side of its side sets with the
 * library's ex_get_side_set_node_list and prints them, one side a line:
 * "SET_ID ELEMENT SIDE: node positions (1-based)".
 *
 *   exo_write OUT FLAVOUR < input        FLAVOUR: classic, 64bit or netcdf4
 *
 * The input, whitespace-separated: the node count, then per node its id
 * and x y z; the block count, then per block its id, name, type, nodes per
 * element and element count, then per element its id and nodes (1-based
 * positions in the node list); the side-set count, then per side set its
 * id, name and side count, then per side the element (1-based position in
 * the file's element order) and the side number.
 * Build: cc -o exo_write exo_write.c -lexoIIv2c -lnetcdf */
#include <exodusII.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void check(int status, const char *what) {
  if (status < 0) { fprintf(stderr, "exo_write: %s failed (%d)\n", what, status); exit(1); }
}

int main(int argc, char **argv) {
  if (argc != 3) { fprintf(stderr, "usage: exo_write OUT FLAVOUR < input\n"); return 2; }
  const char *out = argv[1], *flavour = argv[2];
  int mode = EX_CLOBBER;
  if (!strcmp(flavour, "classic")) mode |= EX_NORMAL_MODEL;
  else if (!strcmp(flavour, "64bit")) mode |= EX_LARGE_MODEL;
  else if (!strcmp(flavour, "netcdf4")) mode |= EX_NETCDF4;
  else { fprintf(stderr, "unknown flavour %s\n", flavour); return 2; }
  int nnodes, nblocks, nsets, nelem = 0;
  if (scanf("%d", &nnodes) != 1) return 3;
  int *node_ids = malloc(sizeof(int) * nnodes);
  double *x = malloc(sizeof(double) * nnodes), *y = malloc(sizeof(double) * nnodes), *z = malloc(sizeof(double) * nnodes);
  for (int i = 0; i < nnodes; i++)
    if (scanf("%d %lf %lf %lf", &node_ids[i], &x[i], &y[i], &z[i]) != 4) return 3;
  if (scanf("%d", &nblocks) != 1) return 3;
  int *block_ids = malloc(sizeof(int) * nblocks), *nper = malloc(sizeof(int) * nblocks), *count = malloc(sizeof(int) * nblocks);
  char **block_names = malloc(sizeof(char *) * nblocks), **types = malloc(sizeof(char *) * nblocks);
  int **conn = malloc(sizeof(int *) * nblocks), *elem_ids = malloc(sizeof(int) * 1000000);
  for (int b = 0; b < nblocks; b++) {
    block_names[b] = malloc(64);
    types[b] = malloc(64);
    if (scanf("%d %63s %63s %d %d", &block_ids[b], block_names[b], types[b], &nper[b], &count[b]) != 5) return 3;
    conn[b] = malloc(sizeof(int) * (count[b] * nper[b] + 1));
    for (int e = 0; e < count[b]; e++) {
      if (scanf("%d", &elem_ids[nelem++]) != 1) return 3;
      for (int j = 0; j < nper[b]; j++)
        if (scanf("%d", &conn[b][e * nper[b] + j]) != 1) return 3;
    }
  }
  if (scanf("%d", &nsets) != 1) return 3;
  int cpu_ws = 8, io_ws = 8;
  int exoid = ex_create(out, mode, &cpu_ws, &io_ws);
  check(exoid, "ex_create");
  check(ex_put_init(exoid, "seam test fixture (SEACAS exodusII)", 3, nnodes, nelem, nblocks, 0, nsets), "ex_put_init");
  check(ex_put_coord(exoid, x, y, z), "ex_put_coord");
  char *coord_names[3] = {"x", "y", "z"};
  check(ex_put_coord_names(exoid, coord_names), "ex_put_coord_names");
  check(ex_put_node_num_map(exoid, node_ids), "ex_put_node_num_map");
  for (int b = 0; b < nblocks; b++) {
    check(ex_put_elem_block(exoid, block_ids[b], types[b], count[b], nper[b], 0), "ex_put_elem_block");
    check(ex_put_elem_conn(exoid, block_ids[b], conn[b]), "ex_put_elem_conn");
  }
  check(ex_put_elem_num_map(exoid, elem_ids), "ex_put_elem_num_map");
  check(ex_put_names(exoid, EX_ELEM_BLOCK, block_names), "ex_put_names (blocks)");
  int *set_ids = malloc(sizeof(int) * (nsets + 1));
  char **set_names = malloc(sizeof(char *) * (nsets + 1));
  for (int s = 0; s < nsets; s++) {
    int n;
    set_names[s] = malloc(64);
    if (scanf("%d %63s %d", &set_ids[s], set_names[s], &n) != 3) return 3;
    int *el = malloc(sizeof(int) * (n + 1)), *sd = malloc(sizeof(int) * (n + 1));
    for (int i = 0; i < n; i++)
      if (scanf("%d %d", &el[i], &sd[i]) != 2) return 3;
    check(ex_put_side_set_param(exoid, set_ids[s], n, 0), "ex_put_side_set_param");
    check(ex_put_side_set(exoid, set_ids[s], el, sd), "ex_put_side_set");
  }
  if (nsets > 0) check(ex_put_names(exoid, EX_SIDE_SET, set_names), "ex_put_names (side sets)");
  check(ex_close(exoid), "ex_close");

  float version;
  exoid = ex_open(out, EX_READ, &cpu_ws, &io_ws, &version);
  check(exoid, "ex_open");
  for (int s = 0; s < nsets; s++) {
    int n_sides, n_df;
    check(ex_get_side_set_param(exoid, set_ids[s], &n_sides, &n_df), "ex_get_side_set_param");
    int *counts = malloc(sizeof(int) * (n_sides + 1)), *nodes = malloc(sizeof(int) * (n_sides * 27 + 1));
    int *el = malloc(sizeof(int) * (n_sides + 1)), *sd = malloc(sizeof(int) * (n_sides + 1));
    check(ex_get_side_set(exoid, set_ids[s], el, sd), "ex_get_side_set");
    check(ex_get_side_set_node_list(exoid, set_ids[s], counts, nodes), "ex_get_side_set_node_list");
    int k = 0;
    for (int i = 0; i < n_sides; i++) {
      printf("%d %d %d:", set_ids[s], el[i], sd[i]);
      for (int j = 0; j < counts[i]; j++) printf(" %d", nodes[k++]);
      printf("\n");
    }
  }
  check(ex_close(exoid), "ex_close");
  return 0;
}
