#!/usr/bin/python3
"""Reads .vtp files with VTK's own XML reader (Debian's python3-vtk9, the reader ParaView uses) and prints, as one
JSON object keyed by file, what the tests compare with the dump and the case geometry: point and cell counts, the
points, every point-data array (name, components, values), the polygon sizes and the bounds. Exit 1 when VTK reports
an error or warning while reading."""
import json
import sys

import vtk


class Errors:
    def __init__(self):
        self.messages = []

    def __call__(self, caller, event):
        self.messages.append(event)


def read(path):
    reader = vtk.vtkXMLPolyDataReader()
    errors = Errors()
    reader.AddObserver("ErrorEvent", errors)
    reader.AddObserver("WarningEvent", errors)
    reader.SetFileName(path)
    reader.Update()
    if errors.messages or reader.GetErrorCode() != 0:
        print(f"{path}: VTK could not read it: {errors.messages} (error code {reader.GetErrorCode()})", file=sys.stderr)
        sys.exit(1)
    data = reader.GetOutput()
    points = data.GetPoints()
    out = {
        "points": data.GetNumberOfPoints(),
        "verts": data.GetNumberOfVerts(),
        "polys": data.GetNumberOfPolys(),
        "bounds": list(data.GetBounds()),
        "coordinates": [list(points.GetPoint(i)) for i in range(data.GetNumberOfPoints())] if points else [],
        "arrays": {},
        "polygon_sizes": [],
    }
    pd = data.GetPointData()
    for k in range(pd.GetNumberOfArrays()):
        array = pd.GetArray(k)
        c = array.GetNumberOfComponents()
        out["arrays"][array.GetName()] = {
            "type": array.GetDataTypeAsString(),
            "components": c,
            "values": [array.GetComponent(i, j) for i in range(array.GetNumberOfTuples()) for j in range(c)],
        }
    polys = data.GetPolys()
    ids = vtk.vtkIdList()
    polys.InitTraversal()
    while polys.GetNextCell(ids):
        out["polygon_sizes"].append(ids.GetNumberOfIds())
    return out


print(json.dumps({path: read(path) for path in sys.argv[1:]}))
