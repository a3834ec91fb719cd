"""A kiln run in ParaView: discs at their true radius, walls as lines, coloured by speed or
temperature with the unit in the colour legend, and the time in a corner.

    pvpython scripts/paraview_view.py out/t3_heap                       # the last frame, on screen
    xvfb-run -a pvpython scripts/paraview_view.py out/t3_heap --screenshot heap.png [--time 0.5]
    in ParaView's Python shell:
        import sys; sys.path.insert(0, 'scripts'); import paraview_view; paraview_view.show('out/t3_heap')

It opens DIR/result.xdmf with ParaView's legacy XDMF reader, the one of ParaView's three that
names the two series (`particles`, `walls`); the Xdmf3 readers read the same values into unnamed
blocks 0 and 1. Each disc is a sphere glyph of diameter 1 seen from +z, scaled by `radius` with a
scale factor of 2 at every point ("All Points": the default masks most of them). The
colour defaults to temperature in thermal runs and to speed (|velocity|) otherwise; units come
from the `units` attributes of result.h5.
"""
import argparse
import os
import sys

import h5py
from paraview import simple as pv

UNITS_SHOWN = {'degC': '\N{DEGREE SIGN}C'}


def units_of(h5_path, dataset):
    with h5py.File(h5_path, 'r') as f:
        u = f[dataset].attrs.get('units', b'')
    u = u.decode() if isinstance(u, bytes) else str(u)
    return UNITS_SHOWN.get(u, u)


def discs(series):
    """The filled circles of a particles series, at their true radius (a pipeline source)."""
    glyph = pv.Glyph(Input=series, GlyphType='Sphere')  # seen from +z: a round disc
    glyph.GlyphType.Radius = 0.5
    glyph.GlyphType.ThetaResolution = 32
    glyph.GlyphType.PhiResolution = 9  # odd: a ring of vertices on the equator, the disc's edge
    glyph.OrientationArray = ['POINTS', 'No orientation array']
    glyph.ScaleArray = ['POINTS', 'radius']
    glyph.ScaleFactor = 2.0  # the glyph's diameter is 1
    glyph.GlyphMode = 'All Points'
    return glyph


def series(reader, name, index):
    """One of the two series: by name in the legacy reader, by place in the Xdmf3 readers."""
    try:
        return pv.ExtractBlock(Input=reader, Selectors=['/Root/' + name])
    except Exception:  # pragma: no cover - older ParaView
        return pv.ExtractBlock(Input=reader, BlockIndices=[index + 1])


class ViewError(Exception):
    """A run directory, time or output the view cannot use: the message says which and why."""


_shown = []  # the proxies the last show() made: a second call replaces them


def show(run_dir, field=None, time=None, screenshot=None, size=(1200, 900)):
    for proxy in reversed(_shown):
        pv.Delete(proxy)
    _shown.clear()
    if pv.GetActiveView() is not None:  # the colour bars of what was deleted
        for array in ('velocity', 'temperature'):
            pv.HideScalarBarIfNotNeeded(pv.GetColorTransferFunction(array), pv.GetActiveView())
    run_dir = os.path.abspath(run_dir)
    if os.path.isfile(run_dir):
        raise ViewError("%s is a file: give the run's directory (%s)" % (run_dir, os.path.dirname(run_dir)))
    h5_path = os.path.join(run_dir, 'result.h5')
    for name in ('result.h5', 'result.xdmf'):
        if not os.path.isfile(os.path.join(run_dir, name)):
            killed = os.path.exists(os.path.join(run_dir, 'result.h5.tmp')) or \
                os.path.exists(os.path.join(run_dir, 'result.h5.unfinished'))
            raise ViewError('%s has no %s: %s' % (run_dir, name, 'a run that did not finish (resume it with kiln run '
                                                  '--restart DIR/checkpoint.h5)' if killed else
                                                  'not a kiln run directory (kiln run writes out/<scene name>/)'))
    if screenshot and not screenshot.lower().endswith('.png'):
        raise ViewError('--screenshot %s: give a file name ending in .png' % screenshot)
    if screenshot and not os.path.isdir(os.path.dirname(os.path.abspath(screenshot))):
        raise ViewError('--screenshot %s: its directory does not exist' % screenshot)
    with h5py.File(h5_path, 'r') as f:
        thermal = 'temperature' in f
        has_walls = 'wall_of_segment' in f
        times = f['time'][:]
        k = len(times) - 1 if time is None else min(range(len(times)), key=lambda i: abs(times[i] - time))
        values = f['temperature'][k] if thermal and field != 'speed' else \
            (f['velocity'][k][:, 0] ** 2 + f['velocity'][k][:, 1] ** 2) ** 0.5
        scene = f.attrs.get('scene', b'')
    scene = scene.decode() if isinstance(scene, bytes) else str(scene)
    field = field or ('temperature' if thermal else 'speed')
    if field == 'temperature' and not thermal:
        raise ViewError('%s has no temperature (not a thermal run); use --field speed' % run_dir)
    if time is not None and not times[0] <= time <= times[-1]:
        raise ViewError("--time %g: the run's frames span [%g, %g] s" % (time, times[0], times[-1]))
    reader = pv.XDMFReader(registrationName='kiln', FileNames=[os.path.join(run_dir, 'result.xdmf')])
    view = pv.GetActiveViewOrCreate('RenderView')
    view.ViewSize = list(size)
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    if hasattr(view, 'UseColorPaletteForBackground'):
        view.UseColorPaletteForBackground = 0
    particles = series(reader, 'particles', 0) if has_walls else reader
    disc = discs(particles)
    shown = pv.Show(disc, view)
    shown.Ambient, shown.Diffuse = 1.0, 0.0  # flat colours: a disc, not a lit ball
    if field == 'temperature':
        pv.ColorBy(shown, ('POINTS', 'temperature'))
        lut = pv.GetColorTransferFunction('temperature')
        title = 'temperature (%s)' % units_of(h5_path, 'temperature')
    else:
        pv.ColorBy(shown, ('POINTS', 'velocity', 'Magnitude'))
        lut = pv.GetColorTransferFunction('velocity')
        title = 'speed (%s)' % units_of(h5_path, 'velocity')
    lut.ApplyPreset('Viridis (matplotlib)', True)
    shown.SetScalarBarVisibility(view, True)
    bar = pv.GetScalarBar(lut, view)
    bar.Title = title
    bar.ComponentTitle = ''
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    if has_walls:
        walls_block = series(reader, 'walls', 1)
        _shown.append(walls_block)
        walls = pv.Show(walls_block, view)
        pv.ColorBy(walls, None)
        walls.AmbientColor = walls.DiffuseColor = [0, 0, 0]
        walls.LineWidth = 3.0
    clock = pv.AnnotateTimeFilter(Input=reader, Format='t = {time:.4g} s')
    label = pv.Show(clock, view)
    label.WindowLocation = 'Upper Left Corner'
    label.Color = [0, 0, 0]
    name = pv.Text(Text=scene)
    caption = pv.Show(name, view)
    caption.WindowLocation = 'Upper Center'
    caption.Color = [0, 0, 0]
    t = times[k]
    scene_ = pv.GetAnimationScene()
    scene_.UpdateAnimationUsingDataTimeSteps()
    scene_.AnimationTime = t
    view.ViewTime = t
    # The frame's own range: the colours of a screenshot span what it shows; a constant field (a
    # run at rest, one temperature) gets a range of 1 % around its value (ParaView's own widening,
    # 1.6e-4, draws a bar whose two ends read alike).
    low, high = float(values.min()), float(values.max())
    if high - low <= 1e-9 * max(abs(low), abs(high)):
        half = max(abs(low) * 0.01, 1e-6)
        low, high = low - half, low + half
    lut.RescaleTransferFunction(low, high)
    lut.AutomaticRescaleRangeMode = 'Never'
    view.InteractionMode = '2D'
    view.ResetCamera()
    pv.Render(view)
    _shown[:0] = [reader] + ([particles] if has_walls else []) + [disc]  # made first: deleted last
    _shown.extend([clock, name])
    if screenshot:
        if not pv.SaveScreenshot(screenshot, view, ImageResolution=list(size)) or not os.path.isfile(screenshot):
            raise ViewError('--screenshot %s: ParaView could not write it' % screenshot)
    return view


def main():
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    p.add_argument('run_dir', help='a kiln run directory (result.xdmf, result.h5)')
    p.add_argument('--field', choices=['speed', 'temperature'])
    p.add_argument('--time', type=float, help='the frame nearest this time (s), the earlier of two as near; default: the last')
    p.add_argument('--screenshot', help='write a PNG here and exit')
    a = p.parse_args()
    try:
        show(a.run_dir, a.field, a.time, a.screenshot)
    except ViewError as e:
        sys.exit('paraview_view: %s' % e)
    if not a.screenshot:
        pv.Interact()


if __name__ == '__main__':
    main()
