"""The independent checkers' modules (../shared/tools beside the checkout) for the bench scripts:
meshio's readers and check_fit.py itself (its sampler and distance), loaded once from there.

  from shared_checkers import check_fit, read_mesh, triangles
"""
import importlib.util
import os
import sys

TOOLS = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', '..', 'shared', 'tools')
sys.path.insert(0, TOOLS)
from meshio import read_mesh, triangles  # noqa: E402,F401

_spec = importlib.util.spec_from_file_location('check_fit', os.path.join(TOOLS, 'check_fit.py'))
check_fit = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(check_fit)
