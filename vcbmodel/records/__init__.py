"""What a record is: measurement files (``NAME.csv``) and the analysis of sampled signals
(noise, swing peaks, decay, disagreement windows). Units follow the channel (s, rad, m).

May import: ``vcbmodel.rig.reader`` (file decoding), ``vcbmodel.errors``, numpy.
"""
