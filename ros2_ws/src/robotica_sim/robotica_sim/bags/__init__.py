"""Bag tooling: crash-safe MCAP writer, rosbag2 metadata, type store, info, play, repair."""

__all__ = ['info', 'metadata', 'player', 'repair', 'typestore', 'writer']
