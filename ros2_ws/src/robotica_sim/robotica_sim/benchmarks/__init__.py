"""Benchmarks behind ``robotica bench``: arm, mobile, tracking, kinematics and recorder speed."""

__all__ = ['arm', 'kinematics', 'measurement_row', 'mobile', 'recorder', 'tracking']
