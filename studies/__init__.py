"""Data of openEMSS installed with it (found as ``openemss.studies``): the folder's files, not code."""
