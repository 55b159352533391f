#!/usr/bin/env python3
"""Side-by-side comparison of seam with the dune-grid-glue 2.9 peer (ggmortar).

Python 3, standard library only.

What it does
------------
1. Converts the peer's simple ASCII ``.mesh`` files (``nodes N`` / N lines
   ``x y z`` / ``faces M`` / M lines ``k i1 .. ik``, 0-based, k = 3 or 4) to
   Gmsh MSH 2.2 ASCII: ``$Nodes`` with tags 1..N in the SAME order (so row i /
   column j of seam's matrices is node i of the peer's file), ``$Elements``
   with type 2 (3-node triangle) or 3 (4-node quad) and the two tags ``1 1``
   (physical 1, entity 1).  Converted files are cached next to the work dir.
2. Runs, one after the other (never two timed processes at once), per case
   and size F:
     * ggmortar SLAVE MASTER              (grid mode, the default)
     * ggmortar SLAVE MASTER --raw        (raw Merger::build, no Dune grid)
     * seam assemble MASTER SLAVE -o DIR --threads 1
     * seam assemble MASTER SLAVE -o DIR --threads 2
   each under ``/usr/bin/time -f %M`` (peak RSS).  On the cylinder cases the
   peer gets ``--overlap 0.02`` (as in its run_bench.sh) and seam
   ``--max-gap 0.02``; flat cases use both tools' defaults.
   Before every timed run the 1-minute load average is checked; if it is
   above --max-load (1.5) the script waits (up to --max-wait seconds) and
   records the load it started at and whether compilers (rustc, cc1plus, ...)
   were running at that moment.
3. For flat cases with F <= --matrix-max, the peer grid run writes
   PREFIX_B.mtx / PREFIX_D.mtx and both are compared entry by entry with
   seam's B.mtx / D.mtx (1-thread run):  max|X_seam - X_peer| / max|X_peer|.
   On ``flatj`` the peer is also run with ``--exact-quad-coords --qorder 12``
   (a harness option that re-projects to the true bilinear coordinates) and
   compared again.  It also checks that seam's 1- and 2-thread matrices are
   byte-identical.

Cases (as in the peer's run_bench.sh; slave first, as ggmortar takes them):
    flat     slave flat_tri_F    master flat_quad_F
    flatj    slave flat_quadj_F  master flat_tri_F
    cyl_gap  slave cyl_quad_F    master cyl_tri_g_F   (overlap / max-gap 0.02)
    cyl_ovl  slave cyl_quad_F    master cyl_tri_o_F   (overlap / max-gap 0.02)

Usage
-----
    python3 scripts/peer_compare.py --peer /tmp/ggpeer --meshes /tmp/ggpeer/meshes \\
        --seam /tmp/seam-bin --sizes 10000,100000,200000 --work /tmp/peer_compare

Prints Markdown tables on stdout (and writes them, plus the raw records as
JSON lines, into the work directory).
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time

CASES = {
    # name: (slave, master, cylinder?)
    "flat": ("flat_tri_{F}", "flat_quad_{F}", False),
    "flatj": ("flat_quadj_{F}", "flat_tri_{F}", False),
    "cyl_gap": ("cyl_quad_{F}", "cyl_tri_g_{F}", True),
    "cyl_ovl": ("cyl_quad_{F}", "cyl_tri_o_{F}", True),
}
CYL_TOL = 0.02
COMPILERS = {"rustc", "cargo", "cc1plus", "cc1", "ld", "ld.lld", "lld", "clippy-driver",
             "rust-analyzer", "build-script-b"}


def log(*a):
    print(*a, file=sys.stderr, flush=True)


# ---------------------------------------------------------------- conversion
def mesh_to_msh(src, dst):
    """Simple ASCII .mesh -> Gmsh MSH 2.2 ASCII, same node order (tags 1..N)."""
    with open(src) as f:
        tok = f.read().split()
    p = 0
    assert tok[p] == "nodes", src
    n = int(tok[p + 1])
    p += 2
    nodes = tok[p:p + 3 * n]
    p += 3 * n
    assert tok[p] == "faces", src
    m = int(tok[p + 1])
    p += 2
    out = ["$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % n]
    for i in range(n):
        # keep the coordinates' text exactly as written (%.17g): no re-rounding
        out.append("%d %s %s %s\n" % (i + 1, nodes[3 * i], nodes[3 * i + 1], nodes[3 * i + 2]))
    out.append("$EndNodes\n$Elements\n%d\n" % m)
    for e in range(m):
        k = int(tok[p])
        ids = tok[p + 1:p + 1 + k]
        p += 1 + k
        if k == 3:
            typ = 2
        elif k == 4:
            typ = 3
        else:
            raise ValueError("%s: face %d has %d nodes" % (src, e, k))
        out.append("%d %d 2 1 1 %s\n" % (e + 1, typ, " ".join(str(int(i) + 1) for i in ids)))
    out.append("$EndElements\n")
    tmp = dst + ".tmp"
    with open(tmp, "w") as f:
        f.write("".join(out))
    os.replace(tmp, dst)


def converted(meshdir, name, cachedir):
    src = os.path.join(meshdir, name + ".mesh")
    dst = os.path.join(cachedir, name + ".msh")
    if not os.path.exists(dst) or os.path.getmtime(dst) < os.path.getmtime(src):
        mesh_to_msh(src, dst)
    return src, dst


# ---------------------------------------------------------------- machine state
def load1():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def compilers_running():
    found = set()
    me = os.getpid()
    for d in os.listdir("/proc"):
        if not d.isdigit() or int(d) == me:
            continue
        try:
            with open("/proc/%s/comm" % d) as f:
                c = f.read().strip()
        except OSError:
            continue
        if c in COMPILERS:
            found.add(c)
    return sorted(found)


def cpu_busy_s():
    """Busy CPU seconds of the whole machine since boot (all cores)."""
    with open("/proc/stat") as f:
        v = [int(x) for x in f.readline().split()[1:]]
    idle = v[3] + (v[4] if len(v) > 4 else 0)
    return (sum(v[:8]) - idle) / os.sysconf("SC_CLK_TCK")


def wait_quiet(max_load, max_wait):
    t0 = time.time()
    l = load1()
    while l > max_load and time.time() - t0 < max_wait:
        log("  load %.2f > %.2f, waiting (%s)" % (l, max_load, ",".join(compilers_running()) or "-"))
        time.sleep(15)
        l = load1()
    return {"load1": l, "waited_s": round(time.time() - t0), "compilers": compilers_running()}


# ---------------------------------------------------------------- runs
def timed(cmd, workdir, timeout, max_load, max_wait):
    state = wait_quiet(max_load, max_wait)
    rssf = os.path.join(workdir, "rss.txt")
    full = ["/usr/bin/time", "-f", "%M %e %U %S", "-o", rssf] + cmd
    log("  $ " + " ".join(cmd))
    t0 = time.time()
    b0 = cpu_busy_s()
    r = subprocess.run(full, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)
    b1 = cpu_busy_s()
    wall = time.time() - t0
    after = compilers_running()
    rss_kb, wall_e, cpu = None, None, None
    try:
        with open(rssf) as f:
            last = f.read().strip().splitlines()[-1].split()
        rss_kb, wall_e, cpu = int(last[0]), float(last[1]), float(last[2]) + float(last[3])
    except (OSError, IndexError, ValueError):
        pass
    # CPU seconds used on the machine during the run by anything but this run
    # (a rough measure of disturbance by other work; ~0.0x is idle noise)
    foreign = (b1 - b0) - cpu if cpu is not None else None
    state.update({"rc": r.returncode, "rss_mb": rss_kb / 1024.0 if rss_kb else None,
                  "wall_s": wall_e if wall_e is not None else wall, "cpu_s": cpu,
                  "foreign_cpu_s": foreign, "compilers_after": after})
    return r, state


def run_peer(args, slave, master, cyl, extra, workdir):
    cmd = [os.path.join(args.peer, "ggmortar"), slave, master] + extra
    if cyl:
        cmd += ["--overlap", str(CYL_TOL)]
    r, st = timed(cmd, workdir, args.timeout, args.max_load, args.max_wait)
    summ = None
    for line in r.stdout.splitlines() + r.stderr.splitlines():
        if line.startswith("SUMMARY"):
            summ = {}
            for t in line.split()[1:]:
                k, _, v = t.partition("=")
                try:
                    summ[k] = float(v)
                except ValueError:
                    summ[k] = v
    if summ is None:
        log("  peer failed rc=%s\n%s\n%s" % (r.returncode, r.stdout[-2000:], r.stderr[-2000:]))
    st["summary"] = summ
    st["cmd"] = cmd
    return st


def run_seam(args, master, slave, cyl, threads, outdir, workdir):
    if os.path.isdir(outdir):
        shutil.rmtree(outdir)
    cmd = [args.seam, "assemble", master, slave, "-o", outdir, "--threads", str(threads)]
    if cyl:
        cmd += ["--max-gap", str(CYL_TOL)]
    r, st = timed(cmd, workdir, args.timeout, args.max_load, args.max_wait)
    summ = None
    try:
        with open(os.path.join(outdir, "summary.json")) as f:
            summ = json.load(f)
    except (OSError, ValueError):
        log("  seam failed rc=%s\n%s\n%s" % (r.returncode, r.stdout[-2000:], r.stderr[-2000:]))
    st["summary"] = summ
    st["cmd"] = cmd
    return st


# ---------------------------------------------------------------- matrices
def read_mtx(path):
    with open(path) as f:
        head = f.readline()
        assert head.lower().startswith("%%matrixmarket matrix coordinate real general"), (path, head)
        line = f.readline()
        while line.startswith("%"):
            line = f.readline()
        nr, nc, nnz = (int(x) for x in line.split())
        d = {}
        for line in f:
            s = line.split()
            if not s:
                continue
            key = (int(s[0]), int(s[1]))
            d[key] = d.get(key, 0.0) + float(s[2])
    return nr, nc, d


def compare_mtx(seam_path, peer_path):
    nr1, nc1, a = read_mtx(seam_path)
    nr2, nc2, b = read_mtx(peer_path)
    if (nr1, nc1) != (nr2, nc2):
        return {"shape_mismatch": [(nr1, nc1), (nr2, nc2)]}
    scale = max((abs(v) for v in b.values()), default=0.0)
    worst, where = 0.0, None
    for k in set(a) | set(b):
        diff = abs(a.get(k, 0.0) - b.get(k, 0.0))
        if diff > worst:
            worst, where = diff, k
    return {"rel": worst / scale if scale else float("nan"), "max_abs": scale, "at": where,
            "nnz_seam": len(a), "nnz_peer": len(b)}


def same_bytes(p, q):
    with open(p, "rb") as f, open(q, "rb") as g:
        return f.read() == g.read()


# ---------------------------------------------------------------- main
def fmt(x, f="%.3f"):
    return "–" if x is None else f % x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--peer", default="/tmp/ggpeer", help="dir with the built ggmortar")
    ap.add_argument("--meshes", default=None, help="dir with gen_meshes.py output [PEER/meshes]")
    ap.add_argument("--seam", default="/tmp/seam-bin", help="seam binary")
    ap.add_argument("--sizes", default="10000,100000,200000")
    ap.add_argument("--cases", default="flat,flatj,cyl_gap,cyl_ovl")
    ap.add_argument("--work", default="/tmp/peer_compare")
    ap.add_argument("--matrix-max", type=int, default=10000,
                    help="compare matrices on flat cases with F <= this")
    ap.add_argument("--no-raw", action="store_true", help="skip the peer's --raw run")
    ap.add_argument("--max-load", type=float, default=1.5)
    ap.add_argument("--max-wait", type=float, default=900)
    ap.add_argument("--timeout", type=float, default=3600)
    args = ap.parse_args()
    meshdir = args.meshes or os.path.join(args.peer, "meshes")
    os.makedirs(args.work, exist_ok=True)
    cache = os.path.join(args.work, "msh")
    os.makedirs(cache, exist_ok=True)
    recfile = open(os.path.join(args.work, "records.jsonl"), "a")

    rows = []
    for F in [int(s) for s in args.sizes.split(",")]:
        for case in args.cases.split(","):
            sname, mname, cyl = CASES[case]
            sname, mname = sname.format(F=F), mname.format(F=F)
            s_mesh, s_msh = converted(meshdir, sname, cache)
            m_mesh, m_msh = converted(meshdir, mname, cache)
            log("== %s F=%d (slave %s, master %s)" % (case, F, sname, mname))
            want_mtx = (not cyl) and F <= args.matrix_max
            pref = os.path.join(args.work, "peer", "%s_%d" % (case, F))
            os.makedirs(os.path.dirname(pref), exist_ok=True)
            rec = {"case": case, "F": F, "slave": sname, "master": mname}
            rec["peer_grid"] = run_peer(args, s_mesh, m_mesh, cyl,
                                        ["--out", pref] if want_mtx else [], args.work)
            if not args.no_raw:
                rec["peer_raw"] = run_peer(args, s_mesh, m_mesh, cyl, ["--raw"], args.work)
            sd = {}
            for t in (1, 2):
                sd[t] = os.path.join(args.work, "seam", "%s_%d_t%d" % (case, F, t))
                rec["seam_t%d" % t] = run_seam(args, m_msh, s_msh, cyl, t, sd[t], args.work)
            if want_mtx:
                mc = {}
                for X in ("B", "D"):
                    mc[X] = compare_mtx(os.path.join(sd[1], X + ".mtx"), "%s_%s.mtx" % (pref, X))
                    mc[X + "_t1_eq_t2"] = same_bytes(os.path.join(sd[1], X + ".mtx"),
                                                     os.path.join(sd[2], X + ".mtx"))
                if case == "flatj":
                    prefx = pref + "_exact"
                    rec["peer_exact"] = run_peer(args, s_mesh, m_mesh, cyl,
                                                 ["--out", prefx, "--exact-quad-coords", "--qorder", "12"],
                                                 args.work)
                    for X in ("B", "D"):
                        mc[X + "_exact"] = compare_mtx(os.path.join(sd[1], X + ".mtx"),
                                                       "%s_%s.mtx" % (prefx, X))
                rec["matrix"] = mc
            recfile.write(json.dumps(rec) + "\n")
            recfile.flush()
            rows.append(rec)

    md = tables(rows, not args.no_raw)
    print(md)
    with open(os.path.join(args.work, "tables.md"), "w") as f:
        f.write(md)


def g(rec, key, *path):
    v = rec.get(key)
    if not v:
        return None
    v = v.get("summary")
    for p in path:
        if v is None:
            return None
        v = v.get(p)
    return v


def tables(rows, raw):
    L = []
    L.append("| case | F | peer grid merge+asm s | peer raw merge+asm s | seam search+asm s (1 thr) "
             "| seam (2 thr) | peer-grid / seam-1thr | covered area: seam vs peer | B, D: max diff / max entry |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        pg = r["peer_grid"]["summary"]
        pr = r.get("peer_raw", {}).get("summary") if raw else None
        s1 = r["seam_t1"]["summary"]
        s2 = r["seam_t2"]["summary"]
        tg = pg["merge_s"] + pg["assembly_s"] if pg else None
        tr = pr["merge_s"] + pr["assembly_s"] if pr else None
        t1 = s1["seconds"]["search"] + s1["seconds"]["assemble"] if s1 else None
        t2 = s2["seconds"]["search"] + s2["seconds"]["assemble"] if s2 else None
        ratio = tg / t1 if tg and t1 else None
        if s1 and pg:
            ca, pa, sa = s1["covered_area"], pg["area"], s1["slave_area"]
            cov = "%.10f vs %.10f (Δ %.1e; uncov. %.1e vs %.1e)" % (
                ca, pa, ca - pa, 1 - ca / sa, 1 - pa / pg["slave_area"])
        else:
            cov = "–"
        mat = ""
        m = r.get("matrix")
        if m:
            mat = "B %.1e, D %.1e" % (m["B"]["rel"], m["D"]["rel"])
            if "B_exact" in m:
                mat += "; vs peer exact-quad q12: B %.1e, D %.1e" % (m["B_exact"]["rel"], m["D_exact"]["rel"])
            if not (m["B_t1_eq_t2"] and m["D_t1_eq_t2"]):
                mat += "; seam 1 vs 2 thr NOT identical"
        L.append("| %s | %d | %s | %s | %s | %s | %s | %s | %s |" % (
            r["case"], r["F"], fmt(tg), fmt(tr), fmt(t1), fmt(t2),
            fmt(ratio, "%.1f×"), cov, mat))
    L.append("")
    L.append("| case | F | peer: read / setup / merge / asm s | peer raw: merge / asm s "
             "| seam 1 thr: read / search / asm / write / total s | seam 2 thr total s "
             "| intersections peer / seam segments | peak RSS MB peer grid / raw / seam 1 / seam 2 "
             "| load1 at start (peer, seam1) | other CPU s during runs (peer grid / raw / seam 1 / seam 2) | compilers seen |")
    L.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        pg = r["peer_grid"]["summary"] or {}
        pr = (r.get("peer_raw") or {}).get("summary") or {}
        s1 = r["seam_t1"]["summary"] or {}
        s2 = r["seam_t2"]["summary"] or {}
        sec = s1.get("seconds", {})
        comp = set()
        for k in ("peer_grid", "peer_raw", "seam_t1", "seam_t2"):
            if k in r:
                comp |= set(r[k]["compilers"]) | set(r[k]["compilers_after"])
        fo = " / ".join(fmt((r.get(k) or {}).get("foreign_cpu_s"), "%.2f")
                        for k in ("peer_grid", "peer_raw", "seam_t1", "seam_t2"))
        L.append("| %s | %d | %s / %s / %s / %s | %s / %s | %s / %s / %s / %s / %s | %s | %s / %s | %s / %s / %s / %s | %.2f, %.2f | %s | %s |" % (
            r["case"], r["F"],
            fmt(pg.get("read_s")), fmt(pg.get("setup_s")), fmt(pg.get("merge_s")), fmt(pg.get("assembly_s")),
            fmt(pr.get("merge_s")), fmt(pr.get("assembly_s")),
            fmt(sec.get("read")), fmt(sec.get("search")), fmt(sec.get("assemble")), fmt(sec.get("write")),
            fmt(sec.get("total")), fmt(s2.get("seconds", {}).get("total")),
            fmt(pg.get("intersections"), "%d"), fmt(s1.get("segments"), "%d"),
            fmt(r["peer_grid"]["rss_mb"], "%.0f"), fmt((r.get("peer_raw") or {}).get("rss_mb"), "%.0f"),
            fmt(r["seam_t1"]["rss_mb"], "%.0f"), fmt(r["seam_t2"]["rss_mb"], "%.0f"),
            r["peer_grid"]["load1"], r["seam_t1"]["load1"], fo, ",".join(sorted(comp)) or "none"))
    return "\n".join(L) + "\n"


if __name__ == "__main__":
    main()
