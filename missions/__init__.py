"""Data of openEMSS installed with it (found as ``openemss.missions``): the folder's files, not code."""
