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
