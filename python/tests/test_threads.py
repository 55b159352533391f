"""Thread count independence (I7) and release of the GIL during assembly."""

import threading
import time

import numpy as np
import pytest

import seam
from meshes import as_input, grid

MASTER = grid(23, 19, "triangles", jitter=0.12)
SLAVE = grid(17, 21, "mixed", jitter=0.1, seed=11)


def assert_same_csr(a, b):
    assert a.shape == b.shape
    np.testing.assert_array_equal(a.indptr, b.indptr)
    np.testing.assert_array_equal(a.indices, b.indices)
    np.testing.assert_array_equal(a.data, b.data)  # bit for bit, not allclose


@pytest.mark.parametrize("multiplier", ["standard", "dual", "lumped"])
def test_one_and_two_threads_give_identical_matrices(multiplier):
    ops = [
        seam.assemble(as_input(*MASTER), as_input(*SLAVE), multiplier, threads=n) for n in (1, 2, None)
    ]
    for op in ops[1:]:
        assert_same_csr(ops[0].B, op.B)
        assert_same_csr(ops[0].D, op.D)
        np.testing.assert_array_equal(ops[0].coverage, op.coverage)
        assert ops[0].summary == op.summary
    v = np.random.default_rng(1).standard_normal(ops[0].shape[1])
    np.testing.assert_array_equal(ops[0].transfer(v), ops[1].transfer(v))


def test_assembly_releases_the_gil():
    """A Python thread keeps running while another one assembles.

    With the GIL held for the whole Rust call, the ticking thread could not run
    until the call returned; it would tick at most once or twice during it.
    """
    big_master = seam.Mesh(*as_input(*grid(160, 160, "triangles", jitter=0.1)))
    big_slave = seam.Mesh(*as_input(*grid(150, 150, "quads")))
    started, done = threading.Event(), threading.Event()
    ticks_during = []
    timing = {}

    def ticker():
        started.wait()
        ticks = 0
        while not done.is_set():
            time.sleep(0.001)
            ticks += 1
        ticks_during.append(ticks)

    thread = threading.Thread(target=ticker)
    thread.start()
    t0 = time.perf_counter()
    started.set()
    seam.assemble(big_master, big_slave, threads=1)
    timing["assemble"] = time.perf_counter() - t0
    done.set()
    thread.join()
    if timing["assemble"] < 0.05:
        pytest.skip(f"assembly too fast ({timing['assemble']:.3f} s) to observe")
    assert ticks_during[0] >= 10, (ticks_during, timing)
