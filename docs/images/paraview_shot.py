# Makes docs/images/paraview.png (docs/visualization.md, "ParaView") with ParaView's pvbatch:
#   linx run examples/slider_crank.json --out out/sc --every 10 --vtk
#   xvfb-run -a pvbatch docs/images/paraview_shot.py out/sc docs/images/paraview.png 0.6
# Needs Debian's paraview, python3-paraview and xvfb, which linx itself does not need.
import sys
from paraview.simple import *
run, out, t = sys.argv[1], sys.argv[2], float(sys.argv[3])
reader = PVDReader(FileName=run + '/run.pvd')
reader.UpdatePipelineInformation()
times = reader.TimestepValues
print('timesteps', len(times), times[:3], times[-1])
view = CreateView('RenderView')
view.ViewSize = [1200, 700]
view.Background = [1, 1, 1]
try:
    view.UseColorPaletteForBackground = 0
except Exception:
    pass
view.OrientationAxesVisibility = 1
disp = Show(reader, view)
ColorBy(disp, ('POINTS', 'velocity', 'Magnitude'))
lut = GetColorTransferFunction('velocity')
disp.SetScalarBarVisibility(view, True)
view.ViewTime = t
reader.UpdatePipeline(t)
hi = 0
for tt in times:
    reader.UpdatePipeline(tt)
    hi = max(hi, reader.PointData['velocity'].GetRange(-1)[1])
lut.RescaleTransferFunction(0.0, hi)
bar = GetScalarBar(lut, view)
bar.Title = 'velocity (m/s)'
bar.ComponentTitle = ''
bar.TitleColor = [0, 0, 0]
bar.LabelColor = [0, 0, 0]
disp.AmbientColor = [0.1, 0.1, 0.1]
disp.DiffuseColor = [0.1, 0.1, 0.1]
disp.PointSize = 12
disp.RenderPointsAsSpheres = 1
view.ResetCamera()
cam = view.GetActiveCamera()
cam.Elevation(-55)
cam.Azimuth(-25)
view.ResetCamera()
cam.Zoom(1.3)
label = Text(Text='linx run examples/slider_crank.json --vtk: run.pvd in ParaView, t = %g s, colour: speed of each surface point' % t)
ld = Show(label, view)
ld.Color = [0, 0, 0]
ld.FontSize = 14
ld.WindowLocation = 'Upper Center'
cam.Zoom(1.15)
Render(view)
SaveScreenshot(out, view, ImageResolution=[1200, 700])
print('saved', out)
