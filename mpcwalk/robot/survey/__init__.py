"""A preset drafted from a humanoid's description alone (``mpcwalk robots init``).

:mod:`~mpcwalk.robot.survey.legs` finds the legs, up and forward from the kinematic tree;
:mod:`~mpcwalk.robot.survey.feet` the soles from the feet's shapes;
:mod:`~mpcwalk.robot.survey.upper_body` the torso and the servos' loads;
:mod:`~mpcwalk.robot.survey.posture` solves the walking posture;
:mod:`~mpcwalk.robot.survey.rules` sizes the servos and the gait;
:mod:`~mpcwalk.robot.survey.draft` puts them together and
:mod:`~mpcwalk.robot.survey.writer` writes the commented preset.
"""
