"""The names of the seven methods of the paper's Fig. 11, (a)-(g).

Kept apart from the pipeline so that the command line can list them without loading
numpy, OpenCV and SciPy.
"""

METHODS = ("global", "local", "elastic", "global+eri", "local+eri", "elastic+eri", "e+md")
