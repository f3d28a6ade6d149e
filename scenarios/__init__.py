"""Data of openEMSS installed with it (found as ``openemss.scenarios``): the folder's files, not code."""
