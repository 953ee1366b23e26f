% ui: kbc run tests/ui/run/aux/truncated.kbb
% A bytecode file cut short after its version: the loader refuses it with the byte offset.
