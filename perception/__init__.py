"""Contacts, vGRF and gait perception — built in the perception issues."""
