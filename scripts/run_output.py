"""Reading a `sphforge run` output folder (docs: DESIGN output contract) from the scripts here:
history.csv as columns and one particles_NNNNNN.vtu frame as arrays. Import it from a script in this
folder (`from run_output import load_history, read_frame, frame_by_id`); the frame reader needs
python3-vtk9 and numpy.
"""
import csv


def load_history(run):
    """history.csv of RUN as {column: [float, ...]}; a run still writing leaves a partial last row,
    which is dropped; empty and "nan" cells read as NaN."""
    with open(f"{run}/history.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if None not in r.values()]
    return {k: [float(r[k]) if r[k] not in ("", "nan") else float("nan") for r in rows] for k in rows[0]}


def read_frame(path):
    """The point arrays of a particles_NNNNNN.vtu frame as {name: numpy array} plus "position",
    and the frame's time (s)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    pd = grid.GetPointData()
    fields = {pd.GetArrayName(k): vtk_to_numpy(pd.GetArray(k)) for k in range(pd.GetNumberOfArrays())}
    fields["position"] = vtk_to_numpy(grid.GetPoints().GetData())
    time = grid.GetFieldData().GetArray("TimeValue")
    return fields, float(time.GetValue(0))


def frame_by_id(fields):
    """The arrays of a frame from read_frame, reordered by the particle id, so that two frames of one
    run line up particle by particle (the core reorders particles for locality between frames)."""
    import numpy as np

    order = np.argsort(fields["id"])
    return {k: v[order] for k, v in fields.items()}
