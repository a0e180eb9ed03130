"""Run by pvpython (check_xdmf_paraview.py starts it under xvfb-run): opens each sidecar given,
with the reader OpenDataFile picks (--reader default), the legacy XDMF reader (--reader
legacy) or Xdmf3ReaderT (--reader xdmf3t), applies Warp By Vector on `displacement` and prints one line per file:
    RESULT {"file": ..., "reader": ..., "steps": ..., "last_time": ..., "points": ...,
            "cells": ..., "components": {...}, "warped_bounds": [...]}
With --png, also renders the last step of the warped result, coloured by the displacement
magnitude, to that file (one PNG per sidecar: NAME.png for NAME.xdmf, in --png's folder).
"""
import argparse
import json
import os

from paraview import simple as pv


def open_file(name, reader):
    if reader == "legacy":
        return pv.XDMFReader(FileNames=[name])
    if reader == "xdmf3t":
        return pv.Xdmf3ReaderT(FileName=[name])
    return pv.OpenDataFile(name)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reader", choices=("default", "legacy", "xdmf3t"), default="default")
    ap.add_argument("--png", default="", help="folder for the PNGs (none: no rendering)")
    ap.add_argument("files", nargs="+")
    a = ap.parse_args()
    for name in a.files:
        r = open_file(name, a.reader)
        times = list(r.TimestepValues)
        last = times[-1]
        r.UpdatePipeline(last)
        info = r.GetDataInformation()
        comps = {k: r.PointData[k].GetNumberOfComponents() for k in r.PointData.keys()}
        warp = pv.WarpByVector(Input=r, Vectors=["POINTS", "displacement"], ScaleFactor=1.0)
        warp.UpdatePipeline(last)
        out = dict(file=name, reader=r.GetXMLName(), steps=len(times), last_time=last,
                   points=info.GetNumberOfPoints(), cells=info.GetNumberOfCells(),
                   components=comps, warped_bounds=list(warp.GetDataInformation().GetBounds()))
        if a.png:
            view = pv.GetActiveViewOrCreate("RenderView")
            view.ViewSize = [1024, 768]
            view.ViewTime = last
            view.OrientationAxesVisibility = 0
            shown = pv.Show(warp, view)
            pv.ColorBy(shown, ("POINTS", "displacement", "Magnitude"))
            shown.RescaleTransferFunctionToDataRange(True, False)
            shown.SetScalarBarVisibility(view, True)
            shown.SetRepresentationType("Surface With Edges")
            text = pv.Text(Text=f"{os.path.basename(name)}  t = {last:.4g}  "
                                f"({r.GetXMLName()}, Warp By Vector x1)")
            pv.Show(text, view)
            view.ResetCamera()
            view.CameraPosition = [view.CameraFocalPoint[0], view.CameraFocalPoint[1],
                                   view.CameraFocalPoint[2] + 10.0]
            view.CameraViewUp = [0.0, 1.0, 0.0]
            view.ResetCamera()
            png = os.path.join(a.png, os.path.splitext(os.path.basename(name))[0] + ".png")
            pv.SaveScreenshot(png, view, ImageResolution=[1024, 768])
            out["png"] = png
            pv.Hide(warp, view)
            pv.Delete(text)
        print("RESULT " + json.dumps(out), flush=True)
        pv.Delete(warp)
        pv.Delete(r)


if __name__ == "__main__":
    main()
