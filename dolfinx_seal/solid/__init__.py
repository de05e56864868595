"""The rubber bulk: materials, kinematics, boundary tractions, the contact problem."""
