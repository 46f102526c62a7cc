"""
robotica_sim: simulators, sensor emulators, bags, runs, grading and the robotica command.

One folder a concern: ``simulation`` (vehicle, arm), ``sensors`` (one model a sensor),
``bags`` (write, inspect, play, repair), ``runs`` (scenario, plan, supervisor), ``grading``
(series, metrics, rubric, summary, report, figures), ``benchmarks``; the ROS 2 shells are in
``nodes`` and the command line in ``cli``; ``batch`` runs sweeps and gradings on Dask.
"""

__all__ = ['bags', 'batch', 'benchmarks', 'cli', 'grading', 'nodes', 'runs', 'sensors',
           'simulation']
