"""Fitting, identification and diagnosis on measurements, and synthetic records.

May import: ``vcbmodel.experiments`` and everything below it.
"""
