% A device, a directory: kbc reads regular files only, and never opens the others (a device
% such as /dev/zero or /dev/urandom never ends; a FIFO blocks until someone writes to it).
:- include('/dev/zero').
:- include('/tmp').
fact.
