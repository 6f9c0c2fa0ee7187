# bash completion for decalcomp (installed to share/bash-completion/completions/decalcomp).
# Subcommands and each subcommand's options come from the program's own --help, so the completion
# never lags behind the CLI; file names complete everywhere else.
_decalcomp() {
    local cur=${COMP_WORDS[COMP_CWORD]} program=${COMP_WORDS[0]} sub="" word
    for word in "${COMP_WORDS[@]:1:COMP_CWORD-1}"; do
        case $word in -*) ;; *) sub=$word; break ;; esac
    done
    if [[ -z $sub ]]; then
        if [[ $cur == -* ]]; then
            mapfile -t COMPREPLY < <(compgen -W "--help --version" -- "$cur")
        else
            # The "Subcommands:" section of the top-level help: one name per line.
            mapfile -t COMPREPLY < <(compgen -W "$("$program" --help 2>/dev/null |
                sed -n '/^Subcommands:/,$ s/^  \([a-z][a-z-]*\) .*/\1/p')" -- "$cur")
        fi
        return
    fi
    if [[ $cur == -* ]]; then
        mapfile -t COMPREPLY < <(compgen -W "$("$program" "$sub" --help 2>/dev/null |
            grep -oE -- '--[a-z][a-z0-9-]*' | sort -u)" -- "$cur")
    fi
}
complete -o default -o bashdefault -F _decalcomp decalcomp
