# Bash completion for pbxmpm: subcommands, their options and file names.
#   source tools/completion/pbxmpm.bash      (or copy it to /etc/bash_completion.d/pbxmpm)
# The subcommands and options are read from `pbxmpm --help` and `pbxmpm SUB --help` the first time
# they are needed, so the completion always matches the binary it completes (CLI11 has no
# completion generator of its own).
_pbxmpm_help_words() {
  # $1: the pbxmpm command; $2: subcommand or empty. Prints subcommands (top) or options (sub).
  if [ -z "$2" ]; then
    "$1" --help 2>/dev/null | awk '/^Subcommands:/{s=1; next} s && NF {print $1}'
  else
    "$1" "$2" --help 2>/dev/null | grep -oE '(^|[ ,])--?[A-Za-z][A-Za-z0-9-]*' | sed 's/^[ ,]//' | sort -u
  fi
}

_pbxmpm() {
  local cur=${COMP_WORDS[COMP_CWORD]} prog=${COMP_WORDS[0]} sub="" i
  for ((i = 1; i < COMP_CWORD; i++)); do
    case ${COMP_WORDS[i]} in -*) ;; *) sub=${COMP_WORDS[i]}; break ;; esac
  done
  if [ -z "$sub" ]; then
    COMPREPLY=($(compgen -W "$(_pbxmpm_help_words "$prog" "") --help --version" -- "$cur"))
  elif [[ $cur == -* ]]; then
    COMPREPLY=($(compgen -W "$(_pbxmpm_help_words "$prog" "$sub")" -- "$cur"))
  else
    COMPREPLY=($(compgen -f -- "$cur"))
  fi
}
complete -o filenames -F _pbxmpm pbxmpm
