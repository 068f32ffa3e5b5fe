"""Open MPI settings that make a LAMMPS start cheap on one machine (bench/lammps_*.py, the tests).

Debian's lmp links Open MPI 4, whose default start loads the cm PML's transports: libpsm2's
constructor alone sleeps ~0.2 s (Omni-Path probing), and an MPI singleton (lmp without mpirun)
spawns an orted daemon. The single collisions of bench/lammps_collisions.py are each one lmp run of
a few hundred steps, so that start was most of their time: 0.5 s per run against 0.04 s with
these settings (the ob1 PML over shared memory, no psm2/ofi transports, an isolated singleton).
Results do not depend on them. Anything already set in the environment wins.
"""
import os

FAST_START = {
    "OMPI_MCA_pml": "ob1",
    "OMPI_MCA_btl": "self,vader",
    "OMPI_MCA_mtl": "^psm2,ofi",
    "OMPI_MCA_ess_singleton_isolated": "1",
}


def fast_mpi_start():
    """Put FAST_START into os.environ (for every lmp or mpirun started from here on)."""
    for k, v in FAST_START.items():
        os.environ.setdefault(k, v)


MPI_START_FAILED = ("ompi_rte_init failed", "An error occurred in MPI_Init")


def run_lmp(args, tries=3, **kw):
    """subprocess.run(args, capture_output=True, text=True, **kw), started again (up to `tries`
    times) when Open MPI's singleton start itself failed ("ompi_rte_init failed" in MPI_Init, seen
    once under heavy load while another lmp started): that failure happens before LAMMPS reads its
    input, so a second start changes no result. Any other failure is returned as it is."""
    import subprocess
    for _ in range(tries):
        p = subprocess.run(args, capture_output=True, text=True, **kw)
        if p.returncode == 0 or not any(m in p.stdout + p.stderr for m in MPI_START_FAILED):
            return p
    return p
