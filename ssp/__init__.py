"""Data of openEMSS installed with it (found as ``openemss.ssp``): the folder's files, not code."""
