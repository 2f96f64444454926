"""The command line ctest gives every tests/cli_*.py script (tests/CMakeLists.txt):
the rast binary under test, its Serial twin, the test data folders and a
scratch folder. A script adds its own options to the parser it gets."""
import argparse


def arg_parser(assimp_default=""):
    ap = argparse.ArgumentParser()
    ap.add_argument("--rast", required=True)
    ap.add_argument("--rast-serial", default="")
    ap.add_argument("--shared", default="")
    ap.add_argument("--assimp", default=assimp_default)
    ap.add_argument("--workdir", required=True)
    return ap
