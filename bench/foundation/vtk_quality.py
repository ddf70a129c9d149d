#!/usr/bin/python3
"""Anchor timing: VTK 9.1's vtkMeshQuality (Verdict) on the same .vtu files the
foundation benchmark measured. Prints one Markdown row per file."""
import sys
import time

import vtk


def measure(path, hexes):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    best = float("inf")
    for _ in range(3):
        quality = vtk.vtkMeshQuality()
        quality.SetInputData(grid)
        if hexes:
            quality.SetHexQualityMeasureToScaledJacobian()
        else:
            quality.SetQuadQualityMeasureToScaledJacobian()
        start = time.perf_counter()
        quality.Update()
        best = min(best, time.perf_counter() - start)
    values = quality.GetOutput().GetCellData().GetArray("Quality")
    low = min(values.GetValue(i) for i in range(values.GetNumberOfTuples()))
    return grid.GetNumberOfCells(), best, low


for path in sys.argv[1:]:
    hexes = "hex" in path
    cells, seconds, low = measure(path, hexes)
    print(f"| {path.split('/')[-1]} | {cells} | {seconds:.3f} | {low:.4f} |")
