"""Analytic models of the bearing (numpy only): kinematics and Hertz line contact, the
quasi-static load distribution with a spall, how a spall holds a roller, inner-race
passages, the contact patch against Hertz."""
