"""Reads a .vtp with VTK's own XML reader (PyPI `vtk`) and prints, as JSON: the counts of
points, lines and polygons, every point- and cell-data array (values, unless --counts), the
field data, and everything VTK wrote to its output window (errors and warnings).

Usage: read_vtp.py FILE.vtp [--counts] [--points]  (--points: every point too, as points_all)
"""
import json
import sys

import vtk
from vtk.util.numpy_support import vtk_to_numpy

log = vtk.vtkStringOutputWindow()
vtk.vtkOutputWindow.SetInstance(log)

path = sys.argv[1]
counts_only = "--counts" in sys.argv
reader = vtk.vtkXMLPolyDataReader()
reader.SetFileName(path)
reader.Update()
data = reader.GetOutput()


def arrays(attributes):
    out = {}
    for i in range(attributes.GetNumberOfArrays()):
        array = attributes.GetArray(i)
        values = vtk_to_numpy(array)
        out[array.GetName()] = {"tuples": int(array.GetNumberOfTuples()), "components": int(array.GetNumberOfComponents())}
        if not counts_only:
            out[array.GetName()]["values"] = values.tolist()
    return out


points = vtk_to_numpy(data.GetPoints().GetData()) if data.GetPoints() else None
print(json.dumps({
    "points": int(data.GetNumberOfPoints()),
    "lines": int(data.GetNumberOfLines()),
    "polys": int(data.GetNumberOfPolys()),
    "point_type": data.GetPoints().GetData().GetDataTypeAsString() if data.GetPoints() else None,
    "first_points": points[:3].tolist() if points is not None else [],
    "points_all": points.tolist() if points is not None and "--points" in sys.argv else [],
    "point_data": arrays(data.GetPointData()),
    "cell_data": arrays(data.GetCellData()),
    "field_data": arrays(data.GetFieldData()),
    "has_normals": data.GetPointData().GetNormals() is not None,
    "log": log.GetOutput(),
}))
