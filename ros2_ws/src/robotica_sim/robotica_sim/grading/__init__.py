"""
Grading a run from its bag.

The one loader (series), the metrics, the rubric, the summary line of ``robotica run``, and
the report: its HTML page (report) and its figures (figures); one bag's grade (entry) and a
folder of submissions' (submissions).
"""

__all__ = ['entry', 'figures', 'metrics', 'report', 'rubric', 'series', 'submissions', 'summary']
