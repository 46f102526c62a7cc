"""
Grading a run from its bag.

The one loader (series), the metrics, the rubric, the summary line of ``robotica run``, and
the report: its HTML page (report) and its figures (figures).
"""

__all__ = ['figures', 'metrics', 'report', 'rubric', 'series', 'summary']
