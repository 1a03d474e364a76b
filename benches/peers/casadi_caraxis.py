"""The car axis alone: `python3 benches/peers/casadi_testset.py caraxis` (see that script).

Install: python3 -m pip install casadi      Run: python3 benches/peers/casadi_caraxis.py
"""
import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the repository
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from casadi_testset import main  # noqa: E402

if __name__ == "__main__":
    main("caraxis")
