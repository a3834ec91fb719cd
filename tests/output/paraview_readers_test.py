"""ParaView's own readers open kiln's result.xdmf, and what they read is result.h5, bit for bit.

    xvfb-run -a pvpython tests/output/paraview_readers_test.py KILN REPO WORK_DIR

Runs four short cases with KILN (fixed walls: T1; walls that rotate: the T7 drum; a periodic cell
with a driven lid: N3; a thermal scene without walls: T4), then, for each case and each of
ParaView's three XDMF readers (XDMFReader, the legacy one; Xdmf3ReaderS; Xdmf3ReaderT), a fresh
pvpython that opens result.xdmf and compares with result.h5 (h5py) at the first, a middle and the
last frame: the frame times; the particles' point count, points and every point array (radius,
velocity, angle, angular_velocity, temperature, id); the walls' points (the rows of wall_segments),
their polylines and wall index, and the frame's wall_force, wall_torque and wall_power as field
data; wall_loads.csv read by ParaView's CSV reader (every frame, every wall's columns, named by
wall and unit); units.csv read by it, a row for every array the reader shows, its unit result.h5's;
that the two series keep their block (and, in the legacy reader, their name) at every
frame. Equality is exact (numpy.array_equal on float64): the readers copy doubles.
Any line a reader prints on stderr fails the test (ParaView's "ERR|", Xdmf3's "Skipping
unrecognized array type", a crash's stack). Last, scripts/paraview_view.py draws N3 into
WORK_DIR/paraview_n3.png, with nothing on stderr, its discs spanning exactly the particles'
extent grown by their radii (true radius). Prints a table: case, reader, frames, result.
"""
import os
import shutil
import subprocess
import sys

PVPYTHON = shutil.which('pvpython') or '/usr/bin/pvpython'  # sys.executable names vtkpython, not installed

READERS = ['XDMFReader', 'Xdmf3ReaderS', 'Xdmf3ReaderT']
# case file, t_end (s): short, with at least three frames each
CASES = [('t1_free_fall.yaml', '0.05', 'fixed walls'),
         ('t7_drum_flights.yaml', '0.02', 'moving walls'),
         ('n3_shear_cell.yaml', '0.03', 'periodic, driven lid'),
         ('t4_two_particle_conduction.yaml', '0.02', 'thermal, no walls')]


def check(run_dir, reader_name):
    """In a fresh pvpython: one reader against result.h5. Raises AssertionError on a difference."""
    import h5py
    import numpy as np
    from paraview import simple as pv
    from paraview import servermanager as sm
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet

    xdmf = os.path.join(run_dir, 'result.xdmf')
    h5 = h5py.File(os.path.join(run_dir, 'result.h5'), 'r')
    times = h5['time'][:]
    walls = 'wall_of_segment' in h5
    make = getattr(pv, reader_name)
    reader = make(FileNames=[xdmf]) if reader_name == 'XDMFReader' else make(FileName=xdmf)
    steps = list(reader.TimestepValues)
    assert np.array_equal(np.array(steps), times), 'frame times %s, result.h5 %s' % (steps[:4], times[:4])

    def array(data, name, where='point'):
        fields = {'point': data.GetPointData(), 'cell': data.GetCellData(), 'field': data.GetFieldData()}[where]
        a = fields.GetArray(name)
        assert a is not None, '%s array %r missing (has %s)' % (
            where, name, [fields.GetArrayName(i) for i in range(fields.GetNumberOfArrays())])
        return vtk_to_numpy(a)

    def frame_of(name, k):
        d = h5[name]
        return d[k] if d.shape[0] == len(times) and name not in ('radius', 'id') else d[:]

    for k in sorted({0, len(times) // 2, len(times) - 1}):
        reader.UpdatePipeline(times[k])
        out = sm.Fetch(reader)
        if walls:
            # Xdmf3ReaderS reads a Domain's grids as the pieces of one partitioned block
            series = out.GetBlock(0) if reader_name == 'Xdmf3ReaderS' else out
            count = series.GetNumberOfBlocks() if series.IsA('vtkMultiBlockDataSet') else series.GetNumberOfPieces()
            assert count == 2, 'two series expected, got %d' % count
            p, w = (series.GetPiece(0), series.GetPiece(1)) if series.IsA('vtkMultiPieceDataSet') else \
                (series.GetBlock(0), series.GetBlock(1))
            if reader_name == 'XDMFReader':  # the legacy reader names them, the same at every frame
                names = [out.GetMetaData(i).Get(vtkMultiBlockDataSet.NAME()) for i in range(2)]
                assert names == ['particles', 'walls'], 'block names at frame %d: %s' % (k, names)
        else:
            assert out.IsA('vtkUnstructuredGrid'), 'one series expected, got %s' % out.GetClassName()
            p, w = out, None
        n = h5['radius'].shape[0]
        assert p.GetNumberOfPoints() == n and p.GetNumberOfCells() == n, \
            'frame %d: %d points, %d cells for %d particles' % (k, p.GetNumberOfPoints(), p.GetNumberOfCells(), n)
        assert np.array_equal(vtk_to_numpy(p.GetPoints().GetData()), h5['position'][k]), 'positions, frame %d' % k
        names = ['radius', 'velocity', 'angle', 'angular_velocity', 'id'] + (['temperature'] if 'temperature' in h5 else [])
        for name in names:
            got, want = array(p, name), frame_of(name, k)
            assert got.dtype.kind == want.dtype.kind and np.array_equal(got, want), '%s, frame %d' % (name, k)
        if w is None:
            continue
        rows = frame_of('wall_segments', k)
        s = rows.shape[0]
        ends = np.column_stack([rows.reshape(2 * s, 2), np.zeros(2 * s)])
        assert w.GetNumberOfCells() == s, 'walls: %d cells for %d segments' % (w.GetNumberOfCells(), s)
        assert np.array_equal(vtk_to_numpy(w.GetPoints().GetData()), ends), 'wall ends, frame %d' % k
        for c in range(s):
            ids = w.GetCell(c).GetPointIds()
            assert [ids.GetId(0), ids.GetId(1)] == [2 * c, 2 * c + 1], 'segment %d' % c
        assert np.array_equal(array(w, 'wall', 'cell'), h5['wall_of_segment'][:]), 'wall of segment'
        for name in ('wall_force', 'wall_torque', 'wall_power'):  # Xdmf3: one tuple of W components
            assert np.array_equal(array(w, name, 'field').ravel(), h5[name][k].ravel()), '%s, frame %d' % (name, k)
    if reader_name == 'XDMFReader':  # units.csv, once per case: a unit for every array the reader shows
        table = sm.Fetch(pv.CSVReader(FileName=[os.path.join(run_dir, 'units.csv')]))
        col = lambda name: [table.GetColumnByName(name).GetValue(r) for r in range(table.GetNumberOfRows())]
        units = {(s, a): (u, d) for s, a, u, d in zip(col('series'), col('array'), col('unit'), col('dataset'))}
        shown = [('particles', 'Points')] + [('particles', p.GetPointData().GetArrayName(i))
                                             for i in range(p.GetPointData().GetNumberOfArrays())]
        if w is not None:
            shown += [('walls', 'Points'), ('walls', 'wall')] + [('walls', w.GetFieldData().GetArrayName(i))
                                                                 for i in range(w.GetFieldData().GetNumberOfArrays())]
        for key in shown + [('both', 'time')]:
            assert key in units, 'units.csv has no row for %s' % (key,)
            unit, dataset = units[key]
            want = h5[dataset].attrs['units']
            assert str(unit) == (want.decode() if isinstance(want, bytes) else want), 'unit of %s' % (key,)
        assert len(units) == len(shown) + 1, 'units.csv rows %s, arrays shown %s' % (sorted(units), shown)
    if walls and reader_name == 'XDMFReader':  # wall_loads.csv, once per case: ParaView's CSV reader
        table = sm.Fetch(pv.CSVReader(FileName=[os.path.join(run_dir, 'result.h5').replace('result.h5', 'wall_loads.csv')]))
        column = lambda name: vtk_to_numpy(table.GetColumnByName(name))
        assert table.GetNumberOfRows() == len(times), 'wall_loads.csv: %d rows' % table.GetNumberOfRows()
        assert np.array_equal(column('time (s)'), times), 'wall_loads.csv time'
        for w, wall in enumerate(h5.attrs['wall_names']):
            wall = wall.decode() if isinstance(wall, bytes) else wall
            for col, want in [(' force_x (N)', h5['wall_force'][:, w, 0]), (' force_y (N)', h5['wall_force'][:, w, 1]),
                              (' torque (N m)', h5['wall_torque'][:, w]), (' power (W)', h5['wall_power'][:, w])]:
                assert np.array_equal(column(wall + col), want), 'wall_loads.csv column %r' % (wall + col)
    return len(times)


def check_view(repo, run_dir, png):
    """scripts/paraview_view.py's discs are at the particles' true radius."""
    import h5py
    import numpy as np
    sys.path.insert(0, os.path.join(repo, 'scripts'))
    import paraview_view
    from paraview import simple as pv
    paraview_view.show(run_dir, screenshot=png)
    with h5py.File(os.path.join(run_dir, 'result.h5'), 'r') as h5:
        x, r = h5['position'][-1], h5['radius'][:]
    glyphs = [s for s in pv.GetSources().values() if s.GetXMLName() == 'Glyph']
    assert len(glyphs) == 1
    b = glyphs[0].GetDataInformation().GetBounds()
    want = [np.min(x[:, 0] - r), np.max(x[:, 0] + r), np.min(x[:, 1] - r), np.max(x[:, 1] + r)]
    # The sphere glyph has vertices along +-x and +-y: its extent is r to the glyph filter's float
    # precision (a scale factor off by 2.5 %, as with an even PhiResolution, fails by 1e-5 m)
    for got, w in zip(b[:4], want):
        assert abs(got - w) <= 4 * np.finfo(np.float32).eps * max(abs(w), r.max()), \
            'disc extent %s, particles %s' % (b[:4], want)
    assert os.path.getsize(png) > 10000, 'screenshot %s is empty' % png


def child(args):
    try:
        if args[0] == '--view':
            check_view(args[1], args[2], args[3])
            print('ok')
        else:
            print('ok %d' % check(args[0], args[1]))
    except AssertionError as e:
        print('FAIL %s' % e)
        sys.exit(1)


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    return p.returncode, p.stdout.strip(), p.stderr.strip()


def main(kiln, repo, work):
    os.makedirs(work, exist_ok=True)
    failures = []
    print('%-34s %-13s %-7s %s' % ('case', 'reader', 'frames', 'result'))
    for case, t_end, what in CASES:
        out = os.path.join(work, case.split('.')[0])
        rc, _, err = run([kiln, 'run', os.path.join(repo, 'cases', case), '--t-end', t_end, '--out', out, '--quiet'])
        if rc != 0:
            failures.append('%s: kiln run failed: %s' % (case, err))
            continue
        for reader in READERS:
            rc, stdout, err = run([PVPYTHON, __file__, out, reader])
            result = stdout.splitlines()[-1] if stdout else ''
            if rc != 0 or err or not result.startswith('ok'):
                failures.append('%s, %s: exit %d, %s\n  stderr: %s' % (case, reader, rc, result, err[:2000]))
            print('%-34s %-13s %-7s %s' % ('%s (%s)' % (case.split('_')[0].upper(), what), reader,
                                           result[3:] if result.startswith('ok') else '-',
                                           'ok' if rc == 0 and not err else 'FAIL'))
    png = os.path.join(work, 'paraview_n3.png')
    view = [PVPYTHON, __file__, '--view', repo, os.path.join(work, 'n3_shear_cell'), png]
    rc, stdout, err = run(view)
    if rc != 0 and 'bad X server connection' in err:
        # Xvfb, not ParaView or kiln: about 1 in 20 connections of a render window to a just-started
        # Xvfb abort so (seen with xvfb-run -a alone); one retry, said in the output.
        print('scripts/paraview_view.py: the X server refused the render window; retried once')
        rc, stdout, err = run(view)
    if rc != 0 or err:
        failures.append('scripts/paraview_view.py: exit %d, %s\n  stderr: %s' % (rc, stdout, err[:2000]))
    print('scripts/paraview_view.py on N3: %s (%s)' % ('ok' if rc == 0 and not err else 'FAIL', png))
    for f in failures:
        print('FAIL ' + f)
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    if len(sys.argv) == 4 and not sys.argv[1].startswith('--') and os.path.isfile(sys.argv[1]):
        main(*sys.argv[1:])
    else:
        child(sys.argv[1:])
