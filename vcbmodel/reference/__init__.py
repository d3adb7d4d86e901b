"""Solves of the experiments without Exudyn (scipy), for verification of the Exudyn models.

May import: ``vcbmodel.laws``, ``vcbmodel.errors``, numpy, scipy.
"""
