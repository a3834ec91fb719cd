#!/usr/bin/env python3
"""bench/shuffle_pile.py IN OUT [SEED]: the pile of IN (a LAMMPS data file, atom_style sphere, with
Velocities) with its atoms numbered at random, as a pile's particles are after it has flowed for a
while: the same discs at the same places, in another order. bench/run.sh times kiln and LAMMPS on
it (the "mixed" group)."""
import os
import random
import sys


def main():
    src, dst = sys.argv[1], sys.argv[2]
    seed = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    lines = open(src).read().split("\n")
    atoms_at = next(k for k, l in enumerate(lines) if l.startswith("Atoms"))
    velocities_at = next(k for k, l in enumerate(lines) if l.startswith("Velocities"))
    n = int(next(l for l in lines if l.strip().endswith(" atoms")).split()[0])
    atoms = {int(l.split()[0]): l.split() for l in lines[atoms_at + 2:atoms_at + 2 + n]}
    velocities = {int(l.split()[0]): l.split() for l in lines[velocities_at + 2:velocities_at + 2 + n]}
    if len(atoms) != n or len(velocities) != n:
        sys.exit(f"{src}: expected {n} atoms and {n} velocities after its section headers")
    ids = sorted(atoms)
    random.Random(seed).shuffle(ids)
    new_atoms, new_velocities = [], []
    for k, old in enumerate(ids, 1):
        new_atoms.append(" ".join([str(k)] + atoms[old][1:]))
        new_velocities.append(" ".join([str(k)] + velocities[old][1:]))
    lines[atoms_at + 2:atoms_at + 2 + n] = new_atoms
    lines[velocities_at + 2:velocities_at + 2 + n] = new_velocities
    with open(dst + ".tmp", "w") as out:
        out.write("\n".join(lines))
    os.replace(dst + ".tmp", dst)


if __name__ == "__main__":
    main()
