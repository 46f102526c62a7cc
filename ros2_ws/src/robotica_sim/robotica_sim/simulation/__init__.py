"""Simulators, pure: the wheeled vehicles of ch. 5 and the arm (Pinocchio dynamics)."""

__all__ = ['arm', 'vehicle']
