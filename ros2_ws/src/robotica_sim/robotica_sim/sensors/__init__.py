"""
Sensor models (book ch. 7), pure and seeded: each turns the true state into a reading.

One module a sensor; the node that wraps it is ``robotica_sim.nodes.<sensor>_emulator``.
"""

__all__ = ['allan', 'compass', 'encoder', 'gps', 'gyro', 'infrared', 'laser', 'preset_terms',
           'range_beams', 'sonar']
